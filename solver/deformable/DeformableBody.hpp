// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file DeformableBody.hpp
/// One deformable unit on its own: a tet mesh of compressible Neo-Hookean material advanced by
/// explicit central differences with lumped mass (seed 002 eq. 1-4, 7-10), under gravity, nodal
/// forces, fixed or velocity-driven nodes, and contact, with Coulomb friction if asked, with static
/// half-spaces (HalfSpaceContact.hpp, HalfSpaceFriction.hpp), with rigid bodies whose poses the
/// caller sets (RigidObstacleContact.hpp) and between the mesh's disconnected parts
/// (BodyContact.hpp, BodyFriction.hpp: several bodies of one material as one mesh, e.g. a unit and
/// its anvil).
///
/// Step (velocity form of central differences, "kick-drift-kick"):
///   v += dt/2 a;  x += dt v;  a = (f_ext + m g + f_c(x) - f_int(x, v)) / m - alpha v;  v += dt/2 a,
/// with the viscous forces taken at the half-step velocity. Prescribed components keep their
/// velocity and take no acceleration.
///
/// Lumped mass: 4-node tets give rho V / 4 to each node. 10-node tets use the HRZ lumping
/// (Hinton, Rock & Zienkiewicz 1976): the diagonal of the consistent mass, scaled to the element
/// mass: rho V / 36 per corner and 4 rho V / 27 per mid-edge node (for straight edges). Row sums
/// of the consistent matrix would give corners a negative mass (-rho V / 20).
///
/// Threads: elements are computed in parallel (OpenMP), each into its own rows of a per-element
/// force array; each node then sums its elements' rows in a fixed order (element index, then
/// local node). No floating-point sum depends on the thread count: 1 and N threads give the same
/// bits.
/// Not thread-safe itself: call from one thread.

#include "deformable/BodyContact.hpp"
#include "deformable/BodyFriction.hpp"
#include "deformable/DeformableMesh.hpp"
#include "deformable/HalfSpaceContact.hpp"
#include "deformable/RigidObstacleContact.hpp"
#include "deformable/NeoHookean.hpp"
#include "deformable/StableStep.hpp"
#include "deformable/TetElement.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace armour::deformable {

struct DeformableSettings {
  MaterialSettings material;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81); ///< (unit: m/s^2), z up as everywhere in armour
  bool fBar = true;                     ///< F-bar on 10-node elements (seed 002 eq. 10); off only to show locking
  /// Mass-proportional damping alpha (unit: 1/s): a force -alpha m v on every node. 0 for
  /// dynamics; to find a static state (damping to rest) about 2 omega_1 of the slowest mode.
  double massDamping = 0.0;
  /// Safety factor on the stable step (unit: -). 0.9: the length estimate is at or below the
  /// element bound for every shape measured (StableStep.hpp); the 10 % covers elements shortened
  /// by compression during the run (concrete strains stay below 1e-3).
  double stepSafety = 0.9;
  /// Selective mass scaling (StableStep.hpp, MassScaling): the largest mass that may be added to
  /// the shortest elements to lengthen the step, as a fraction of the body's mass (unit: -). 0 =
  /// off. The added mass is mass like any other (gravity and inertia act on it): 0.01 makes the
  /// model at most 1 % heavier, concentrated in the smallest elements (slivers of gmsh meshes).
  double massScaling = 0.0;
  /// Static half-spaces the body may touch (a rigid anvil, a floor): frictionless potential
  /// contact (HalfSpaceContact.hpp). Empty: no contact.
  std::vector<HalfSpace> halfSpaces;
  /// Potential gradient G of the half-spaces (unit: Pa/m): contact pressure G x depth. 0 = 10 E / h
  /// with h the mean edge of the surface triangles: a contact layer ten times stiffer than a
  /// surface element, so a pressure sigma sinks in by sigma h / (10 E).
  double contactGradient = 0.0;
  /// Coulomb coefficient of the half-spaces and the rigid bodies (unit: -), 0 = frictionless
  /// (HalfSpaceFriction.hpp): each pressed surface node sticks to an anchor by a tangential spring
  /// capped at mu times its normal force (on a rigid body the anchor moves with it).
  double friction = 0.0;
  /// Tangential stiffness of a node's stick spring over its normal contact stiffness G A_a
  /// (unit: -), in (0, 1]. 8/9: Mindlin's 2 (1 - nu) / (2 - nu) at nu = 0.2, the rigid solver's
  /// default (simulation::Material::tangentialStiffnessRatio).
  double frictionStiffnessRatio = 8.0 / 9.0;
  /// Contact with rigid bodies (RigidObstacleContact.hpp), whose poses the caller sets before each
  /// step (setObstacles). The potential gradient is the half-spaces' G (contactGradient); the
  /// stable step counts it. With `friction`, Coulomb friction as on the half-spaces.
  bool rigidContact = false;
  /// Contact between the disconnected parts of the mesh (BodyContact.hpp). Off: parts pass
  /// through each other.
  bool bodyContact = false;
  /// Munjiza's penalty p of the body contact (unit: Pa): potential 4 p lambda_min, a pressure
  /// 4 p d / H at depth d under a face of an element of altitude H. 0 = 2 E: a pressure sigma
  /// sinks in by sigma H / (8 E), below 1e-4 H for concrete stresses (< 20 MPa); stiffer only
  /// shortens the step (the contact frequency grows as sqrt(p)).
  double contactPenalty = 0.0;
  /// Contact damping of the body contact (unit: -): a pressure zeta rho c_d w with w the closing
  /// speed; 0 for elastic contact.
  double contactDamping = 0.0;
  /// Coulomb coefficient between the deformable bodies (unit: -), 0 = frictionless
  /// (BodyFriction.hpp): each pressed surface node sticks to a material point of the other body
  /// by a tangential spring (frictionStiffnessRatio of the body contact's stiffness) capped at mu
  /// times its normal force. Needs bodyContact.
  double bodyFriction = 0.0;
};

/// The dynamic state, all that a restart needs besides the mesh, settings and boundary conditions.
struct DeformableState {
  double time = 0.0;              ///< (unit: s)
  std::uint64_t steps = 0;
  bool accelerationsReady = false;
  std::vector<Vec3> positions;     ///< (unit: m)
  std::vector<Vec3> velocities;    ///< (unit: m/s)
  std::vector<Vec3> accelerations; ///< at `positions` (unit: m/s^2)
  /// Friction stick anchors (HalfSpaceFriction.hpp), half-space h's node n at h x nodes + n (unit:
  /// m); empty without friction.
  std::vector<Vec3> frictionAnchors;
  std::vector<std::uint8_t> frictionActive; ///< 1 where the anchor above is set
  /// Friction anchors of the body contact (BodyFriction.hpp), one per node: the target tet (-1:
  /// none) and the barycentric coordinates in it; empty without body friction.
  std::vector<std::int32_t> bodyFrictionTets;
  std::vector<std::array<double, 4>> bodyFrictionWeights;
};

/// Wall time spent in each stage of the step since the body was made (unit: s).
struct DeformableStepTimes {
  double elementForces = 0.0; ///< internal forces of every element (parallel over elements)
  double gather = 0.0;        ///< nodal sums, loads and accelerations (parallel over nodes)
  double update = 0.0;        ///< kicks, drift and the non-finite guard
};

/// A step that cannot go on (inverted element, non-finite state): names the element or node and
/// the time.
class DeformableStepError : public std::runtime_error {
public:
  explicit DeformableStepError(const std::string& message) : std::runtime_error(message) {}
};

class DeformableBody {
public:
  /// Throws core::InputError naming `source` for a bad material or settings value, an empty mesh,
  /// an element that is inverted or flat, or a node that belongs to no element.
  DeformableBody(DeformableMesh mesh, const DeformableSettings& settings, std::string source = "deformable body");

  [[nodiscard]] const DeformableMesh& mesh() const { return mesh_; }
  [[nodiscard]] const std::string& source() const { return source_; } ///< the name given, for messages
  [[nodiscard]] const DeformableSettings& settings() const { return settings_; }
  [[nodiscard]] const ElementModel& model() const { return model_; }
  [[nodiscard]] const std::vector<ElementGeometry>& geometry() const { return geometry_; }
  [[nodiscard]] std::size_t nodeCount() const { return mesh_.nodeCount(); }
  [[nodiscard]] const std::vector<double>& masses() const { return masses_; } ///< lumped (unit: kg)
  /// The mass scaling applied (factors 1 and no added mass when settings().massScaling is 0).
  [[nodiscard]] const MassScaling& massScaling() const { return massScaling_; }

  [[nodiscard]] const std::vector<Vec3>& positions() const { return state_.positions; }
  [[nodiscard]] const std::vector<Vec3>& velocities() const { return state_.velocities; }
  [[nodiscard]] double time() const { return state_.time; }
  [[nodiscard]] std::uint64_t steps() const { return state_.steps; }
  void setPositions(const std::vector<Vec3>& positions);   ///< e.g. a prescribed initial deformation
  void setVelocities(const std::vector<Vec3>& velocities); ///< initial velocities (unit: m/s)

  /// Prescribe the velocity of `node` on the axes of `axes` (bit 0: x, 1: y, 2: z); other axes
  /// stay free. A fixed node is fixNode(node) (velocity 0 on all axes).
  void fixNode(std::size_t node, const Vec3& velocity = Vec3::Zero(), unsigned axes = 7U);
  [[nodiscard]] unsigned fixedAxes(std::size_t node) const { return fixedAxes_[node]; }
  /// Constant external nodal force (unit: N), added to gravity.
  void setExternalForce(std::size_t node, const Vec3& force);
  [[nodiscard]] const std::vector<Vec3>& externalForces() const { return externalForces_; }

  /// The stable step of this mesh and material (StableStep.hpp) with settings().stepSafety.
  [[nodiscard]] const StableStepEstimate& stableStep() const { return stable_; }
  /// Advance by dt. Throws core::InputError when dt is not positive or above stableStep().dt (the
  /// limit, l_min, c_d and the element named) or when massDamping x dt > 1, DeformableStepError
  /// on an inverted element or a non-finite state.
  void step(double dt);
  /// Evaluate the forces and accelerations at the current state, if not done yet (the first
  /// step does it too): obstacleLoads() and nodalContactForces() then belong to the current
  /// positions and obstacle poses. Throws as step() does on an inverted element.
  void prepare();

  [[nodiscard]] const DeformableStepTimes& stepTimes() const { return times_; }

  /// Internal nodal forces at the current state (unit: N); computed if not ready.
  [[nodiscard]] std::vector<Vec3> internalForces();
  [[nodiscard]] double kineticEnergy() const;       ///< 1/2 sum m v^2 (unit: J)
  [[nodiscard]] double strainEnergy() const;        ///< sum of element stored energies (unit: J)
  [[nodiscard]] double gravityPotential() const;    ///< -sum m g . x (unit: J)
  /// Energy of the half-space contacts at the current positions (unit: J). The body contact has
  /// no energy of its own (Munjiza's distribution, BodyContact.hpp): not included.
  [[nodiscard]] double contactEnergy() const;
  /// Total contact force on the body from the half-spaces at the current positions, with the
  /// friction and the rigid bodies' contact of the last force evaluation (unit: N); the
  /// body contact sums to zero over the mesh (per part: nodalContactForces()).
  [[nodiscard]] Vec3 contactForce() const;
  /// The rigid bodies the body touches in the next force evaluation, at their poses at the end of
  /// the next step (settings().rigidContact; throws core::InputError otherwise). Their level sets
  /// must outlive the body or the next call.
  void setObstacles(std::vector<RigidObstacle> obstacles);
  [[nodiscard]] const std::vector<RigidObstacle>& obstacles() const { return obstacles_; }
  /// What the contact did to each rigid body at the last force evaluation, in setObstacles' order.
  [[nodiscard]] const std::vector<ObstacleLoad>& obstacleLoads() const { return obstacleLoads_; }
  /// Body contact (null when settings().bodyContact is off).
  [[nodiscard]] const BodyContact* bodyContact() const { return bodyContact_.get(); }
  /// Contact forces on each node, half-space and body contact, at the last force evaluation (unit: N).
  [[nodiscard]] const std::vector<Vec3>& nodalContactForces() const { return contactForces_; }
  /// Totals of the body contact at the last force evaluation.
  [[nodiscard]] const BodyContactStats& bodyContactStats() const { return bodyContactStats_; }
  /// Sum of the magnitudes of the body friction forces on the contactor nodes at the last force
  /// evaluation (unit: N); 0 without settings().bodyFriction.
  [[nodiscard]] double bodyFrictionTotal() const { return bodyFrictionTotal_; }
  [[nodiscard]] double contactGradient() const { return contactGradient_; } ///< G in use (unit: Pa/m)
  /// Mean Cauchy stress of each element (unit: Pa), tension positive.
  [[nodiscard]] std::vector<Mat3> elementStresses() const;

  [[nodiscard]] const DeformableState& state() const { return state_; }
  /// Restore a state of this body (checkpoint); throws core::InputError on a size mismatch.
  void restore(const DeformableState& state, const std::string& source);

private:
  void buildNodeElementTable();
  void computeAccelerations();
  void checkStep(double dt) const;
  void gatherElement(std::size_t e, NodeMatrix& x, NodeMatrix& v) const;
  /// f(e, x, v) of every element e, with its nodes' positions x and velocities v, in parallel
  /// (each element writes its own entry; defined in DeformableBody.cpp, used there only).
  template <typename T, typename F>
  std::vector<T> perElement(F&& f) const;

  DeformableMesh mesh_;
  DeformableSettings settings_;
  std::string source_;
  ElementModel model_;
  std::vector<ElementGeometry> geometry_;
  std::vector<double> masses_;
  StableStepEstimate stable_;
  MassScaling massScaling_;
  std::vector<unsigned> fixedAxes_;
  std::vector<Vec3> prescribedVelocity_;
  std::vector<Vec3> externalForces_;
  DeformableState state_;
  DeformableStepTimes times_;
  std::vector<double> elementForces_;       ///< element e, local node a, axis k at (e * nen + a) * 3 + k (unit: N)
  std::vector<std::uint8_t> elementFailed_; ///< per element: 1 if inverted in the last force pass
  std::vector<std::int64_t> nodeSlotStart_; ///< CSR: node n's rows in elementForces_ are nodeSlots_[start[n]..start[n+1])
  std::vector<std::int64_t> nodeSlots_;
  std::vector<SurfaceTriangle> surface_;    ///< for contact: the surface as flat triangles
  double contactGradient_ = 0.0;            ///< G (unit: Pa/m)
  std::vector<Vec3> contactForces_;         ///< per node, at the last force evaluation (unit: N)
  std::vector<double> frictionStiffness_;   ///< per node: kappa G A_a, 0 off the surface (unit: N/m); empty without friction
  std::vector<Vec3> halfSpaceScratch_;      ///< one half-space's normal nodal forces (friction only)
  std::vector<double> bodyFrictionStiffness_; ///< per node: kappa (4 p / H)_max A_a (unit: N/m); empty without body friction
  ContactorLoads contactorLoads_;           ///< the body contact's contactor side (body friction only)
  double bodyFrictionTotal_ = 0.0;          ///< sum of |f| of the body friction at the last evaluation (unit: N)
  std::vector<RigidObstacle> obstacles_;    ///< rigid bodies in contact (setObstacles)
  std::vector<ObstacleLoad> obstacleLoads_; ///< their loads at the last evaluation
  Vec3 frictionTotal_ = Vec3::Zero();       ///< sum of the half-spaces' friction forces at the last evaluation (unit: N)
  std::vector<Vec3> frictionScratch_;       ///< one rigid body's friction forces per node (unit: N)
  std::shared_ptr<const BodyContact> bodyContact_;
  BodyContactStats bodyContactStats_;
};

} // namespace armour::deformable

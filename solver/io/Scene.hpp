// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Scene.hpp
/// What `armour run scene.yaml` simulates: materials, shapes, bodies, the static boundary
/// (planes, slopes with a toe, random height fields, walls, fixed meshes) and the run settings.
///
/// Plain data, fully resolved by the reader (io/SceneReader.hpp): defaults applied, names turned
/// into indices, grids expanded into bodies, Euler angles turned into unit quaternions, paths made
/// absolute, height fields generated. Nothing here depends on YAML. The file format, with a figure
/// of the slope, is docs/scene-file.md.
///
/// Axes: x onshore (wave direction), y along the trunk, z up. SI units throughout.
/// This is cold input data: the dynamics stage copies what it needs into contiguous arrays.

#include "hydro/HydroSettings.hpp"
#include "placement/PlacementSettings.hpp"
#include "simulation/RestSettings.hpp"
#include "simulation/StepSettings.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armour::io {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Quat = Eigen::Quaterniond;

/// A contact material. Two bodies in contact combine their materials in the contact stage.
struct Material {
  std::string name;
  double density = 2400.0;       ///< mass density (unit: kg/m^3); 2350-2400 for armour concrete
  double frictionStatic = 0.75;  ///< Coulomb friction to start sliding (unit: -); 0.75 in seed 001
  double frictionDynamic = 0.75; ///< Coulomb friction while sliding (unit: -); <= frictionStatic
  /// Energy lost in a collision: exactly one of the two is set, as the file gives it. The contact
  /// law turns a restitution into the damping ratio of its clamped spring-dashpot (docs/theory.md,
  /// "Contact law"); the conversion is left to it so that there is one formula in the code.
  std::optional<double> restitution = 0.05; ///< normal coefficient of restitution (unit: -, (0, 1]); 0.05 in seed 001
  std::optional<double> dampingRatio;       ///< damping / critical damping of the contact patch (unit: -)
  /// Penalty modulus p (unit: Pa). Contact law: force per surface sample = p x depth x tributary
  /// area / L, with L the contact law's length scale (docs/theory.md). The default 1e9 Pa is
  /// about 3 % of concrete's Young's modulus: stiff enough that the overlap under self-weight is
  /// rho g L / p ~ 5e-5 L and a 1 m/s impact stays near v sqrt(rho / p) ~ 1.5e-3 L, far below
  /// the overlap guard rail, while the stable time step (proportional to 1/sqrt(p)) stays about
  /// 5 times longer than with p = E. See docs/scene-file.md, "Materials".
  double penalty = 1.0e9;
  /// Tangential / normal contact stiffness (unit: -). Default: Mindlin's ratio 2(1-nu)/(2-nu)
  /// for concrete's Poisson ratio nu = 0.2, i.e. 8/9.
  double tangentialStiffnessRatio = 8.0 / 9.0;
};

/// Where a body's (or several bodies') surface comes from.
enum class ShapeSource { Generator, MeshFile };

/// A shape: a shape-library generator with parameters and seed, or a surface mesh file. Sizes
/// are not part of the shape: each body gives its own.
struct ShapeSpec {
  std::string name;                     ///< the name in `shapes:`, the generator name, or "mesh:<file>"
  ShapeSource source = ShapeSource::Generator;
  std::string generator;                ///< shape-library name (Generator), e.g. "dolos"
  std::map<std::string, double> params; ///< generator parameters given (others take defaults)
  std::uint64_t seed = 1;               ///< for random generators (rock, voronoi-rock)
  std::filesystem::path meshFile;       ///< absolute path (MeshFile); checked to exist at load
};

/// One rigid body. Its reference point is its centroid.
struct Body {
  std::string name;                ///< unique; "body<i>" by default, grids add "_<ix>_<iy>_<iz>"
  std::size_t shape = 0;           ///< index into Scene::shapes
  std::size_t material = 0;        ///< index into Scene::materials
  /// Target volume (unit: m^3): the shape is scaled uniformly to it. Unset only for a mesh file
  /// used at its own size times `scale`.
  std::optional<double> volume;
  double scale = 1.0;              ///< uniform scale of a mesh file when volume is unset (unit: -)
  Vec3 position = Vec3::Zero();    ///< centroid in the world (unit: m)
  Quat orientation = Quat::Identity(); ///< body frame -> world, unit quaternion (unit: -)
  Vec3 velocity = Vec3::Zero();    ///< centroid velocity (unit: m/s)
  Vec3 angularVelocity = Vec3::Zero(); ///< in world axes (unit: rad/s)
  bool fixed = false;              ///< never moves (infinite mass), still collides
};

/// A field of square cells laid on a base plane that rises along +x with gradient tanAlpha; the
/// centre of each cell is lowered vertically by a depth drawn from U(0, maxDepth) (seed 001,
/// section 2.2), giving a shallow pyramidal hollow per cell. Cells are squares measured in the
/// base plane: cell (ix, iy) spans [ix, ix+1] x cellSize along the plane's x direction
/// (cos a, 0, sin a) and [iy, iy+1] x cellSize along y, from `origin`.
struct HeightField {
  Vec3 origin = Vec3::Zero();      ///< corner of cell (0, 0) on the base plane (unit: m)
  double tanAlpha = 0.0;           ///< gradient of the base plane along +x (unit: -)
  int cellsX = 0;                  ///< cells along the plane's x direction (unit: -)
  int cellsY = 0;                  ///< cells along y (unit: -)
  double cellSize = 1.0;           ///< side of a cell in the base plane (unit: m); 1 m in seed 001
  double maxDepth = 0.0;           ///< h: depths are U(0, h) (unit: m)
  std::uint64_t seed = 1;          ///< std::mt19937_64 seed of the depths
  /// Depth of each cell below the base plane (unit: m), index iy * cellsX + ix, drawn in that
  /// order as maxDepth x (raw >> 11) x 2^-53 from std::mt19937_64(seed): portable, in [0, h).
  std::vector<double> depths;

  [[nodiscard]] double depth(int ix, int iy) const { return depths[static_cast<std::size_t>(iy * cellsX + ix)]; }
  /// Unit vector along the cells' x direction in the base plane.
  [[nodiscard]] Vec3 alongX() const;
  /// Corner (ix, iy) on the base plane, 0 <= ix <= cellsX, 0 <= iy <= cellsY (unit: m).
  [[nodiscard]] Vec3 corner(int ix, int iy) const;
  /// The lowered centre of cell (ix, iy): base-plane centre minus depth along z (unit: m).
  [[nodiscard]] Vec3 lowCentre(int ix, int iy) const;
};

/// Fill `field.depths` from its seed and maxDepth (cellsX, cellsY set). Deterministic on every
/// platform: std::mt19937_64 is fully specified; the raw bits are turned into doubles by hand
/// rather than by std::uniform_real_distribution, whose algorithm is implementation-defined.
void generateDepths(HeightField& field);

/// Half-space below a plane: solid on the side opposite to the normal.
struct StaticPlane {
  std::string name;
  std::size_t material = 0;
  Vec3 point = Vec3::Zero();       ///< a point on the plane (unit: m)
  Vec3 normal = Vec3::UnitZ();     ///< unit normal pointing out of the solid (unit: -)
};

/// Slope with a toe, extruded along y (infinite in y; bound it with walls). Profile z(x), solid
/// below, from offshore to onshore (docs/scene-file.md has the figure):
///   seabed at zb = origin.z - toeHeight up to the toe's foot at x = origin.x - toeBaseWidth;
///   toe front face up to (origin.x - toeTopWidth, origin.z); toe top, level, to the origin;
///   slope face rising with gradient tanAlpha to the crest edge at height crestHeight;
///   level crest onshore of it. toeHeight = 0: no toe, the seabed is level with the origin.
struct StaticSlope {
  std::string name;
  std::size_t material = 0;
  Vec2 origin = Vec2::Zero();      ///< (x, z) of the slope foot on the toe top (unit: m)
  double tanAlpha = 0.5;           ///< slope gradient rise/run (unit: -); 0.5 is 1:2
  double crestHeight = 10.0;       ///< crest above the origin (unit: m)
  double toeHeight = 0.0;          ///< toe top above the seabed (unit: m); 0 = no toe
  double toeTopWidth = 0.0;        ///< level toe top, offshore of the origin (unit: m)
  double toeBaseWidth = 0.0;       ///< from the origin to the toe's foot, >= toeTopWidth (unit: m)
  /// Random hollows on the slope face (origin.x to the crest edge), or none.
  std::optional<HeightField> roughness;
};

/// The (x, z) vertices of a slope's profile from the toe's foot (or the origin without a toe)
/// to the crest edge; the profile continues level beyond both ends.
std::vector<Vec2> slopeProfile(const StaticSlope& slope);
/// Height of a slope's smooth profile (without roughness) at x (unit: m).
double slopeHeight(const StaticSlope& slope, double x);

/// A plane with random hollows: a StaticPlane through the field's base plane whose cells inside
/// the field are lowered (HeightField).
struct StaticHeightField {
  std::string name;
  std::size_t material = 0;
  HeightField field;
};

/// Axis-aligned plane bounding the domain in x or y.
struct StaticWall {
  std::string name;
  std::size_t material = 0;
  int axis = 1;                    ///< 0 = x, 1 = y (unit: -)
  double position = 0.0;           ///< coordinate of the wall on its axis (unit: m)
  bool atMinimum = true;           ///< bounds the low side: bodies stay at coordinate > position
  /// Normal pointing into the domain (out of the wall's solid side).
  [[nodiscard]] Vec3 normal() const;
};

/// A fixed closed mesh (rocks, a crown wall): vertex p of the file goes to R (scale p) + position.
struct StaticMesh {
  std::string name;
  std::size_t material = 0;
  std::filesystem::path file;      ///< absolute path; checked to exist at load
  Vec3 position = Vec3::Zero();    ///< translation of the file's origin (unit: m)
  Quat orientation = Quat::Identity(); ///< rotation about the file's origin (unit: -)
  double scale = 1.0;              ///< uniform scale about the file's origin (unit: -)
};

/// The fixed boundary. Its solid is the union of all items.
struct StaticGeometry {
  std::vector<StaticPlane> planes;
  std::vector<StaticSlope> slopes;
  std::vector<StaticHeightField> heightFields;
  std::vector<StaticWall> walls;
  std::vector<StaticMesh> meshes;
  [[nodiscard]] std::size_t size() const {
    return planes.size() + slopes.size() + heightFields.size() + walls.size() + meshes.size();
  }
};

struct TimeStepSettings {
  bool automatic = true;           ///< choose dt from the contact stiffness and the lightest body
  double value = 0.0;              ///< fixed time step when !automatic (unit: s)
  double safety = simulation::kTimeStepSafety; ///< fraction of the stability limit used when automatic (unit: -)
};

/// Which contact model the narrow phase uses (docs/theory.md, "Contact law" and "FDEM potential contact").
enum class ContactModel { LevelSet, Fdem };

/// Which solver turns contacts into motion (docs/theory.md, "The constraint solver").
enum class ContactSolver { Penalty, Constraint };

/// How the penalty law's dashpot is stepped (docs/theory.md section 6, "The dashpot over a step").
enum class ContactDashpot { Explicit, Implicit };

/// Contact model and resolution, relative to each body's nominal diameter Dn = V^(1/3). The
/// defaults are those of the contact stage (contact::SurfaceSampleSettings, contact::LevelSetSettings,
/// contact::FdemMeshSettings).
struct ContactSettings {
  /// levelset: surface samples against level sets (the default: 3 to 5 times cheaper per step
  /// once bodies rest on bodies, no reach limit; docs/fidelity.md); fdem: Munjiza's potential over
  /// tetrahedral contact elements.
  ContactModel model = ContactModel::LevelSet;
  /// penalty: the contact law's forces, explicit steps below the contact's stability limit;
  /// constraint: impulses on reduced points, steps of 1/200 s (contact.constraint).
  ContactSolver solver = ContactSolver::Penalty;
  /// penalty solver: explicit (the dashpot on the half-step velocity) or implicit (trapezoidal in
  /// the dashpot: a low restitution no longer shortens the automatic step, rebounds further from e).
  ContactDashpot dashpot = ContactDashpot::Explicit;
  simulation::ConstraintSettings constraint; ///< contact.constraint: the constraint solver's settings
  /// fdem: tetrahedra per body before the deep ones are dropped (unit: -); seed 002: ~2500 per Core-Loc.
  std::size_t fdemElementsPerUnit = 2500;
  double sampleSpacing = 0.1;      ///< spacing of surface sample points / Dn (unit: -)
  double levelSetCellsPerDn = 24.0; ///< level-set grid cells per Dn (unit: -)
  /// Guard rail: a penetration deeper than this fraction of Dn stops the run, naming the bodies
  /// (unit: -). A quarter of Dn is some 150 times the overlap of a 1 m/s impact at the default
  /// penalty: it trips on a blow-up or on bodies that start inside each other, not on physics.
  double maxOverlap = 0.25;
  /// Near-sample lists of the narrow phase: slack x the smaller Dn (docs/theory.md section 7); exact, a
  /// speed setting only; 0 = off.
  double sampleListSlack = 0.05;
};

struct OutputSettings {
  std::filesystem::path folder;    ///< absolute; default "<scene stem>-out" beside the scene file
  bool folderGiven = false;        ///< `folder` came from the file or a --set, not the default
  double vtkInterval = 0.1;        ///< between VTK snapshots (unit: s of simulated time); 0 = none
  double seriesInterval = 0.01;    ///< between time-series rows (unit: s); 0 = none
  /// Between checkpoints (checkpoint.nc, for `armour run --restart`) (unit: s of simulated time);
  /// 0 = only at the end of the run (and when it is stopped by a signal or a guard rail).
  double checkpointInterval = 1.0;
  double checkpointWallMinutes = 30.0; ///< also between checkpoints (unit: min of wall-clock time); 0 = none
  bool contacts = false;           ///< also write contact points and forces with each snapshot
  /// Bodies whose contact loads are recorded for `armour stress` (<folder>/unit_loads/,
  /// simulation/UnitLoads.hpp): body names, or name prefixes ending in '*' ("unit_*"); empty = none.
  std::vector<std::string> unitLoads;
  double unitLoadsInterval = 0.02; ///< between unit-load records, each the peak of its window (unit: s)
  double unitLoadsCluster = 0.1;   ///< largest width of one recorded load's cluster of contact points (unit: Dn)
};


struct Scene {
  std::string name;                    ///< the scene file's stem, e.g. "pile"
  std::string sourceName;              ///< the file as named by the user (for messages)
  std::filesystem::path baseDir;       ///< folder relative paths are resolved against
  std::string description;             ///< free text from the file
  /// `initial_state:` the state `armour place` left the pack in (its contacts' friction springs
  /// included), which `armour run`/`storm` start from instead of the bodies' positions alone;
  /// absolute, or empty for none.
  std::filesystem::path initialState;
  Vec3 gravity{0.0, 0.0, -9.81};       ///< (unit: m/s^2)
  double duration = 0.0;               ///< simulated time (unit: s)
  TimeStepSettings timeStep;
  std::uint64_t seed = 1;              ///< default seed of random shapes, height fields and grid jitter
  ContactSettings contact;
  OutputSettings output;
  simulation::SleepSettings sleep;
  simulation::BodyDamping bodyDamping;
  std::vector<Material> materials;
  std::vector<ShapeSpec> shapes;       ///< named shapes first, then those bodies used directly
  std::vector<Body> bodies;
  StaticGeometry statics;
  /// Hydrodynamic loads (`hydro:`); hydro.enabled is false without the block. The storm file path
  /// is made absolute against the scene's folder.
  hydro::HydroSettings hydro;
  /// Units to add with `armour place` (`placement:`); placement.enabled is false without the block.
  placement::PlacementSettings placement;
  std::vector<std::string> warnings;   ///< non-fatal notes from reading (also logged)

  /// Index of the material called `name`, or -1.
  [[nodiscard]] std::ptrdiff_t findMaterial(const std::string& name) const;
  /// Index of the body called `name`, or -1.
  [[nodiscard]] std::ptrdiff_t findBody(const std::string& name) const;
};

/// Tait-Bryan angles x-y'-z'' (seed 001, section 2.2): rotate by phi about x, then by theta
/// about the new y', then by psi about the new z''. Equals Rx(phi) Ry(theta) Rz(psi). Radians.
Quat quaternionFromTaitBryan(double phi, double theta, double psi);

/// Every resolved setting with its unit, defaults included, one per line (for the run log).
std::string describeScene(const Scene& scene);

/// What the contacts' state depends on (model, sample spacing, level-set and fdem resolution), one
/// line: a state saved under other settings does not fit the contacts of these.
std::string describeContactModel(const ContactSettings& contact);

/// The scene bodies `output.unit_loads` names, in scene order, or why they cannot be traced.
struct UnitLoadSelection {
  std::vector<std::size_t> bodies;
  std::string problem; ///< "" or what is wrong with an entry (a name of no body, a fixed body), with the fix
};
[[nodiscard]] UnitLoadSelection selectUnitLoadBodies(const Scene& scene);

/// selectUnitLoadBodies' bodies; throws core::InputError naming the scene file, the key and the
/// problem.
std::vector<std::size_t> unitLoadBodies(const Scene& scene);

} // namespace armour::io

// SPDX-License-Identifier: GPL-3.0-or-later
// The energy guard rail (EnergyGuardSettings, docs/theory.md section 7): E - W may not rise, and
// the mechanical energy reported to callers.
#include "simulation/World.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace armour::simulation {

void World::checkEnergy() {
  const EnergyGuardSettings& g = settings_.energyGuard;
  double kinetic = 0.0, potential = 0.0, weightScale = 0.0;
  BodyId hottest = 0;
  double hottestEnergy = -1.0;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    const double m = bodies_.info(b).mass;
    const double ke = bodies_.kineticEnergy(b);
    kinetic += ke;
    potential -= m * settings_.gravity.dot(bodies_.position(b));
    const double dn = bodyDn(b);
    weightScale = std::max(weightScale, m * settings_.gravity.norm() * dn);
    if (ke > hottestEnergy) {
      hottestEnergy = ke;
      hottest = b;
    }
  }
  const double net = kinetic + potential + contactEnergy_ - externalWork_;
  energyPeak_ = std::max(energyPeak_, kinetic + contactEnergy_);
  if (!energyStarted_) {
    energyStarted_ = true;
    energyMinimum_ = net;
    return;
  }
  const double tolerance = g.growthPerBodyWeight * weightScale + g.growthPerPeakEnergy * energyPeak_;
  if (net > energyMinimum_ + tolerance) {
    throw SimulationError(fmt::format(
        "t = {:.6g} s: the energy grew by {:.4g} J without work from outside (kinetic {:.4g} J, contact {:.4g} J; "
        "tolerance {:.4g} J); the integration is unstable, fastest body: {} ({:.4g} J): lower the time step or "
        "the penalty modulus, or raise the restitution damping",
        time_, net - energyMinimum_, kinetic, contactEnergy_, tolerance, bodies_.describe(hottest), hottestEnergy));
  }
  energyMinimum_ = std::min(energyMinimum_, net);
}

double World::mechanicalEnergy() const {
  double e = 0.0;
  for (BodyId b = 0; b < bodies_.size(); ++b) {
    if (bodies_.motionType(b) == dynamics::MotionType::Static) {
      continue;
    }
    e += bodies_.kineticEnergy(b) - bodies_.info(b).mass * settings_.gravity.dot(bodies_.position(b));
  }
  return e;
}

} // namespace armour::simulation

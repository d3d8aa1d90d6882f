// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/DesignVerdicts.hpp"

#include "analysis/DesignFormulas.hpp"
#include "core/Error.hpp"

#include <fmt/format.h>

#include <functional>

namespace armour::analysis {

std::vector<FormulaResult> designVerdicts(const DesignInputs& in) {
  std::vector<FormulaResult> formulas;
  const auto attempt = [&](const char* name, const char* source, const std::function<void(FormulaResult&)>& f) {
    FormulaResult r;
    r.name = name;
    r.source = source;
    if (!std::isfinite(in.ns))
      r.note = in.noHs;
    else if (!std::isfinite(in.cotAlpha))
      r.note = "no slope: give --cot";
    else {
      try {
        f(r);
        r.applicable = true;
      } catch (const core::InputError& e) {
        r.note = std::string("not applicable: ") + e.what();
      }
    }
    formulas.push_back(std::move(r));
  };
  attempt("Hudson", "Hudson (1959); SPM (1984); CEM (2006)", [&](FormulaResult& r) {
    const HudsonCoefficient& c = hudsonCoefficient(in.unitType);
    const double kd = in.breaking ? c.kdBreaking : c.kdNonBreaking;
    const double nsH = hudsonStabilityNumber(kd, in.cotAlpha);
    r.source += "; K_D: " + c.source;
    r.values = {{"K_D", kd}, {"Ns_hudson", nsH}, {"Ns_storm", in.ns}, {"Ns_ratio", in.ns / nsH}};
    r.note =
        fmt::format("{} ({} waves); no damage (0-5 % displaced) expected while Ns_storm <= Ns_hudson: {}",
                    c.description, in.breaking ? "breaking" : "non-breaking", in.ns <= nsH ? "within" : "exceeded");
    if (in.cotAlpha < c.cotMin - 1e-9 || in.cotAlpha > c.cotMax + 1e-9)
      r.note += fmt::format("; K_D is given for cot alpha {}-{}, the slope is {:.3g}", c.cotMin, c.cotMax, in.cotAlpha);
  });
  const bool isRock = in.unitType == "rock" || in.unitType == "voronoi-rock";
  if (isRock) {
    attempt("van der Meer rock", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (rock)", "no mean period Tm: give --tm");
      const RockDamage d =
          vanDerMeerRockDamage({in.ns, in.steepness, in.cotAlpha, in.permeability, in.waves});
      r.values = {{"S", d.damage},
                  {"xi_m", d.iribarren},
                  {"xi_mc", d.iribarrenCritical},
                  {"N", in.waves},
                  {"P", in.permeability}};
      r.note = d.plunging ? "plunging waves" : "surging waves";
    });
    attempt("Melby and Kobayashi", "Melby and Kobayashi (1998)", [&](FormulaResult& r) {
      if (!std::isfinite(in.tm)) core::failInput("Melby and Kobayashi", "no mean period Tm: give --tm");
      const ProgressedDamage d =
          melbyKobayashiDamage({{in.duration, in.ns, in.tm}}, in.cotAlpha, {in.xi});
      r.values = {{"S", d.damage}, {"sigma_S", d.standardDeviation}, {"t_s", in.duration}};
      r.note = "mean damage after the run's duration, one stage of constant Hs and Tm";
    });
  } else if (in.unitType == "cube") {
    attempt("van der Meer cubes", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (cubes)", "no mean period Tm: give --tm");
      r.values = {{"Nod", vanDerMeerCubesNod(in.ns, in.waves, in.steepness, in.cotAlpha)}, {"N", in.waves}};
      r.note = "displaced units per Dn-wide strip after N waves";
    });
  } else if (in.unitType == "tetrapod") {
    attempt("van der Meer tetrapods", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (tetrapods)", "no mean period Tm: give --tm");
      r.values = {{"Nod", vanDerMeerTetrapodsNod(in.ns, in.waves, in.steepness, in.cotAlpha)},
                  {"N", in.waves}};
      r.note = "displaced units per Dn-wide strip after N waves";
    });
  } else if (in.unitType == "accropode") {
    attempt("van der Meer Accropode", "van der Meer (1988)", [&](FormulaResult& r) {
      if (!std::isfinite(in.steepness)) core::failInput("van der Meer (Accropode)", "no mean period Tm: give --tm");
      const AccropodeStability a = vanDerMeerAccropode(in.ns, in.steepness, in.cotAlpha);
      r.values = {{"Ns_start_of_damage", a.startOfDamage}, {"Ns_failure", a.failure}, {"Ns_storm", in.ns}};
      r.note = a.verdict;
    });
  }

  return formulas;
}

} // namespace armour::analysis

// SPDX-License-Identifier: GPL-3.0-or-later
// The scene schema as data (issue 27): the tables of the blocks whose key tables in
// docs/scene-file.md are generated from them (`armour schema --update-doc docs/scene-file.md`).
// Each default is read from the settings struct the block fills, so the docs cannot drift from
// the code; the reader (SceneReader.cpp) checks keys and words its messages from the same table.
#include "io/SceneTables.hpp"

#include <numbers>

namespace armour::io::tables {

using namespace schema;

namespace {

/// "`levelset`": a choice's default as the docs show it.
std::string showChoice(const KeyList& choices, std::size_t index) { return fmt::format("`{}`", choices[index]); }

const KeyList kModels{"levelset", "fdem"};
const KeyList kSolvers{"penalty", "constraint"};
const KeyList kDashpots{"explicit", "implicit"};
const KeyList kSleepScopes{"island", "neighbours"};

} // namespace

const Table& top() {
  static const Table table = [] {
    const Scene d;
    return Table("top", {
      {.name = "description", .kind = KeyKind::Other, .defaultText = "\"\"",
       .meaning = R"md(free text, copied to the run log)md", .type = "text"},
      {.name = "seed", .kind = KeyKind::Integer, .num = {"-"}, .defaultText = fmt::format("{}", d.seed),
       .meaning = R"md(default seed of random shapes, height fields and grid jitter)md",
       .intWhat = "the default seed of random shapes, height fields and grid jitter"},
      {.name = "initial_state", .kind = KeyKind::Other, .defaultText = "none", .meaning =
        R"md(the state file `armour place` writes beside a placed scene (`<stem>-placed-state.nc`): a new run )md"
        R"md(starts from it (positions, velocities, contacts and their friction springs; every body awake, )md"
        R"md(time 0) instead of from the bodies' positions alone. Refused if the scene's bodies are not the )md"
        R"md(state's (names, order, positions to 1 um))md", .type = "path"},
      {.name = "gravity", .kind = KeyKind::Other, .num = {"m/s^2"},
       .defaultText = fmt::format("[{}, {}, {}]", d.gravity.x(), d.gravity.y(), d.gravity.z()), .type = "[x, y, z]"},
      {.name = "duration", .num = {"s", kPositive, "duration: 10, simulated seconds"}, .defaultText = "required",
       .meaning = R"md(simulated time)md"},
      {.name = "time_step", .kind = KeyKind::Other, .num = {"s"},
       .defaultText = d.timeStep.automatic ? "auto" : show(d.timeStep.value), .meaning =
        R"md(`auto`: the largest stable step for the stiffest contact and lightest body, times )md"
        R"md(`time_step_safety`)md", .type = "`auto` or number > 0"},
      {.name = "time_step_safety", .num = {"-", kFraction, "0.2 of the stability limit"},
       .defaultText = show(d.timeStep.safety), .meaning = R"md(fraction of the stability limit used by `auto`)md"},
      {.name = "contact", .kind = KeyKind::Other, .meaning = R"md(see [Contact](#contact))md", .type = "mapping"},
      {.name = "output", .kind = KeyKind::Other, .meaning = R"md(see [Output](#output))md", .type = "mapping"},
      {.name = "sleep", .kind = KeyKind::Other, .meaning = R"md(see [Sleep](#sleep))md", .type = "mapping"},
      {.name = "body_damping", .kind = KeyKind::Other, .defaultText = "off",
       .meaning = R"md(see [Body damping](#body-damping))md", .type = "mapping"},
      {.name = "materials", .kind = KeyKind::Other, .defaultText = "required",
       .meaning = R"md(see [Materials](#materials))md", .type = "mapping name -> material"},
      {.name = "shapes", .kind = KeyKind::Other, .defaultText = "none", .meaning = R"md(see [Shapes](#shapes))md",
       .type = "mapping name -> shape"},
      {.name = "bodies", .kind = KeyKind::Other, .defaultText = "required (optional with `placement`)",
       .meaning = R"md(see [Bodies](#bodies))md", .type = "list"},
      {.name = "static", .kind = KeyKind::Other, .defaultText = "none",
       .meaning = R"md(see [Static geometry](#static-geometry))md", .type = "list"},
      {.name = "hydro", .kind = KeyKind::Other, .defaultText = "none",
       .meaning = R"md(loads of the water on the units: see [Hydrodynamic loads](#hydrodynamic-loads))md",
       .type = "mapping"},
      {.name = "placement", .kind = KeyKind::Other, .defaultText = "none",
       .meaning = R"md(units for `armour place` to add: see [placement.md](placement.md))md", .type = "mapping"},
    });
  }();
  return table;
}

const Table& materials() {
  static const Table table = [] {
    const Material d;
    return Table("materials", {
      {.name = "density", .num = {"kg/m^3", kPositive, "2400 for concrete, 2650 for rock"}, .defaultText = "required",
       .meaning = R"md(2350-2400 for armour concrete (seed 001: 2350), 2650 for rock)md"},
      {.name = "friction", .kind = KeyKind::Other,
       .num = {"-", kNonNegative, "0.75 (seed 001), 0.6 for concrete on rock"}, .defaultText = "required", .meaning =
        R"md(Coulomb coefficients; a single number sets both; dynamic <= static. Seed 001 uses 0.75 for both )md"
        R"md((0.6 is usual for concrete on rock; the higher value stands in for the interlocking the smooth )md"
        R"md(underlayer lacks))md", .type = "number >= 0, or `{static, dynamic}`"},
      {.name = "restitution", .num = {"-", kFraction, "0.05 for concrete (seed 001)"}, .defaultText = "one of the two",
       .meaning = R"md(normal coefficient of restitution; seed 001: 0.05)md"},
      {.name = "damping_ratio", .num = {"-", kNonNegative, "0.3; 1 = critical"}, .defaultText = "one of the two",
       .meaning = R"md(damping over critical damping of the contact patch's spring-dashpot)md"},
      {.name = "penalty", .num = {"Pa", kPositive, "1e9 (about 3 % of concrete's Young's modulus)"},
       .defaultText = show(d.penalty), .meaning = R"md(penalty modulus p of the contact law (below))md"},
      {.name = "tangential_stiffness_ratio", .num = {"-", kFraction, "0.889 (Mindlin, Poisson ratio 0.2)"},
       .defaultText = fmt::format("8/9 = {:.3f}", d.tangentialStiffnessRatio),
       .meaning = R"md(tangential over normal contact stiffness)md"},
    });
  }();
  return table;
}

const Table& contact() {
  static const Table table = [] {
    const ContactSettings d;
    return Table("contact", {
      {.name = "model", .kind = KeyKind::Choice, .defaultText = showChoice(kModels, static_cast<std::size_t>(d.model)),
       .meaning =
        R"md(`levelset`: surface samples against level sets (docs/theory.md, sections 6-7). `fdem`: Munjiza's )md"
        R"md(potential over tetrahedral contact elements (docs/theory.md, "FDEM potential contact"); same )md"
        R"md(friction, damping, guard rails and output. Level set is the default: at the same face stiffness )md"
        R"md(it is 3 to 5 times faster once bodies rest on bodies, has no reach limit and does not soften )md"
        R"md(with depth (docs/fidelity.md))md", .choices = kModels},
      {.name = "solver", .kind = KeyKind::Choice,
       .defaultText = showChoice(kSolvers, static_cast<std::size_t>(d.solver)),
       .meaning =
        R"md(`penalty`: the contact law's forces at every sample point, explicit steps below the stability )md"
        R"md(limit of the stiffest contact (7e-5 to 4e-4 s for armour units; `time_step: auto`). )md"
        R"md(`constraint`: velocity-level contact constraints on at most four reduced points per contact )md"
        R"md(patch, solved with substeps, warm starts and exact Coulomb friction at steps of 1/200 s )md"
        R"md((docs/theory.md, "The constraint solver"). Both read the same narrow phase; `constraint` needs )md"
        R"md(`model: levelset`. Also `--set contact.solver=constraint`)md", .choices = kSolvers},
      {.name = "dashpot", .kind = KeyKind::Choice,
       .defaultText = showChoice(kDashpots, static_cast<std::size_t>(d.dashpot)),
       .meaning =
        R"md(how the penalty solver steps the contact law's dashpot (docs/theory.md section 6, "The dashpot )md"
        R"md(over a step"). `explicit`: on the half-step velocity; the stable step shrinks as the restitution )md"
        R"md(falls (omega dt < 2 (sqrt(1 + zeta^2) - zeta): 0.70 at e = 0.1, 0.21 at e = 0.01). `implicit`: )md"
        R"md(trapezoidal in the dashpot; omega dt < h with h^2 (1 + zeta h) = 4 (1.25 at e = 0.1, 0.88 at e = )md"
        R"md(0.01), so `time_step: auto` takes 1.78 (e = 0.1) to 4.3 (e = 0.01) times longer steps, for )md"
        R"md(rebounds a little further from e (a cube dropped flat: 0.0116 for 0.01, 0.0479 for 0.05) and a )md"
        R"md(first-order transient error about six times the explicit one's ([fidelity.md](fidelity.md) for )md"
        R"md(what it changes in storm damage). Ignored, with a warning, under `constraint`. Also `--set )md"
        R"md(contact.dashpot=implicit`)md", .choices = kDashpots},
      {.name = "constraint", .kind = KeyKind::Other,
       .meaning = R"md(settings of the constraint solver (below); ignored, with a warning, under `penalty`)md",
       .type = "mapping"},
      {.name = "fdem", .kind = KeyKind::Other,
       .meaning = R"md(settings of the fdem model (below); ignored, with a warning, under `levelset`)md",
       .type = "mapping"},
      {.name = "sample_spacing", .num = {"Dn", kFraction, "0.1"}, .defaultText = show(d.sampleSpacing),
       .meaning = R"md(spacing of the surface sample points)md"},
      {.name = "level_set_cells_per_dn", .num = {"cells per Dn", kPositive, "24"},
       .defaultText = show(d.levelSetCellsPerDn),
       .meaning = R"md(resolution of each shape's level-set grid (24 puts 8 cells across a dolos fluke end))md"},
      {.name = "max_overlap", .num = {"Dn", kFraction, "0.25"}, .defaultText = show(d.maxOverlap),
       .meaning =
        R"md(guard rail: a deeper penetration stops the run, naming the bodies. About 150 times the overlap )md"
        R"md(of a 1 m/s impact at the default penalty: it trips on a blow-up or on bodies that start inside )md"
        R"md(each other, not on physics)md"},
      {.name = "sample_list_slack", .num = {"Dn", kUnitInterval, "0.05; 0 = no near-sample lists"},
       .defaultText = show(d.sampleListSlack), .meaning =
        R"md(near-sample lists of the narrow phase (docs/theory.md section 7): a pair's full search lists the )md"
        R"md(samples within the margin plus this x the smaller Dn, and the pair tests only those until it has )md"
        R"md(moved about a third of it. Exact (the same contact points, bit for bit), so a speed setting )md"
        R"md(only; 0 = full searches every step)md"},
    });
  }();
  return table;
}

const Table& contactFdem() {
  static const Table table = [] {
    const ContactSettings d;
    return Table("contact.fdem", {
      {.name = "elements_per_unit", .kind = KeyKind::Integer, .num = {"tetrahedra per body"},
       .defaultText = fmt::format("{}", d.fdemElementsPerUnit), .meaning =
        R"md(the shape's tetrahedral mesh (the seed's Core-Loc resolution); only the elements with a face on )md"
        R"md(the surface take part. Finer meshes resolve the shape's surface better but soften deep overlaps )md"
        R"md(more (docs/theory.md) and cost more; an overlap between two bodies deeper than 0.8 x the )md"
        R"md((median) depth of their surface elements' centroids stops the run)md",
       .intMin = 24, .intMax = 2'000'000, .intWhat = "tetrahedra per body, e.g. 2500 (seed 002)",
       .overMax = "tetrahedra per body; 2500 (seed 002) resolves a Core-Loc"},
    });
  }();
  return table;
}

const Table& contactConstraint() {
  static const Table table = [] {
    const simulation::ConstraintSettings d;
    return Table("contact.constraint", {
      {.name = "time_step", .num = {"s", {simulation::kMinConstraintStep, simulation::kMaxConstraintStep, false, false},
                                     "0.005 (1/200 s), between 1e-6 and 1/30 s"},
       .defaultText = show(d.timeStep), .meaning =
        R"md(the step when the top-level `time_step` is `auto` (a fixed top-level `time_step` wins); 1/200 s )md"
        R"md(divides the storm's record interval of 0.05 s. Steps outside the range are refused: above 1/30 s )md"
        R"md(a storm's records are skipped and the speculative margin no longer covers a falling unit's )md"
        R"md(travel)md", .type = "number in [1e-6, 1/30]"},
      {.name = "substeps", .kind = KeyKind::Integer, .num = {"-"}, .defaultText = fmt::format("{}", d.substeps),
       .meaning =
        R"md(substeps per step: velocities, solve, positions and relax each substep. 3 since session 20: the )md"
        R"md(physics suite passes with 3 as with 4, and the storm damage stays inside the penalty reference's )md"
        R"md(spread, at 0.85 of the cost ([fidelity.md](fidelity.md), "Substeps of the constraint solver"); 2 )md"
        R"md(is cheaper still but lets a tower of ten cubes move 1.04 mm in 60 s)md", .intMin = 1, .intMax = 64,
       .intWhat = "substeps per step, e.g. 3", .overMax = "substeps; use a smaller time_step instead"},
      {.name = "damping_ratio", .num = {"-", kNonNegative, "10"}, .defaultText = show(d.dampingRatio),
       .meaning =
        R"md(damping of each contact point's spring over its critical damping (Box2D v3's default; 1 lets a )md"
        R"md(tower of ten cubes rock for 10 s, 10 settles it in 2 s))md"},
      {.name = "push_speed", .num = {"m/s", kPositive, "3"}, .defaultText = show(d.pushSpeed),
       .meaning = R"md(the largest speed at which an overlap is pushed out)md"},
      {.name = "restitution_threshold", .num = {"m/s", kNonNegative, "0.2"},
       .defaultText = show(d.restitutionThreshold),
       .meaning = R"md(impacts slower than this are inelastic (the restitution of the materials applies above it))md"},
      {.name = "speculative_margin", .num = {"Dn", {0.0, 0.5, true, false}, "0.05"},
       .defaultText = show(d.speculativeMargin),
       .meaning =
        R"md(gap within which contacts are found before they touch, so that an approach is stopped at the )md"
        R"md(surface instead of inside it)md"},
      {.name = "patch_angle", .num = {"rad", {0.0, std::numbers::pi / 2.0, true, true}, "0.5"},
       .defaultText = show(d.patchAngle),
       .meaning = R"md(largest angle between the normals of the points of one contact patch)md",
        .type = "number in (0, pi/2)"},
      // The range depends on speculative_margin: the reader checks it (SceneReader.cpp).
      {.name = "reuse_distance", .num = {"Dn"}, .defaultText = show(d.reuseDistance) + " (at most half the margin)",
       .meaning =
        R"md(a pair that has moved less than this against its partner since its last full narrow phase keeps )md"
        R"md(its contact patches, moved with the bodies ([theory.md](theory.md), "Manifold reuse"); 0 = a )md"
        R"md(full narrow phase for every pair at every step)md",
         .type = "number in [0, min(speculative_margin / 2, 0.05)]"},
      {.name = "friction_anchors", .kind = KeyKind::Flag, .defaultText = show(d.frictionAnchors),
       .meaning =
        R"md(a sticking point's slip is carried from step to step and pulled back ([theory.md](theory.md), )md"
        R"md("Friction"; measured there: it stops a tilted pack's slow creep sooner, changes no storm damage, )md"
        R"md(and is off by default))md"},
    });
  }();
  return table;
}

const Table& output() {
  static const Table table = [] {
    const OutputSettings d;
    return Table("output", {
      {.name = "folder", .kind = KeyKind::Other, .defaultText = "`<scene stem>-out`",
       .meaning = R"md(relative to the scene file's folder)md",
       .type = "path"},
      {.name = "vtk_interval", .num = {"s", kNonNegative, "0.1; 0 = none"}, .defaultText = show(d.vtkInterval),
       .meaning = R"md(between VTK snapshots; 0 = none)md"},
      {.name = "series_interval", .num = {"s", kNonNegative, "0.01; 0 = none"}, .defaultText = show(d.seriesInterval),
       .meaning = R"md(between time-series rows; 0 = none)md"},
      {.name = "checkpoint_interval", .num = {"s", kNonNegative, "1 simulated second; 0 = only at the end"},
       .defaultText = show(d.checkpointInterval), .meaning =
        R"md(between checkpoints (`checkpoint.nc`, for `armour run --restart`) in simulated time; 0 = only at )md"
        R"md(the end of the run (and when it is stopped by a signal or a guard rail))md"},
      {.name = "checkpoint_wall_minutes", .num = {"min", kNonNegative, "30; 0 = none"},
       .defaultText = show(d.checkpointWallMinutes),
        .meaning = R"md(also between checkpoints in wall-clock time; 0 = none)md"},
      {.name = "contacts", .kind = KeyKind::Flag, .defaultText = show(d.contacts),
       .meaning = R"md(also write the contact points and forces with each snapshot)md"},
      {.name = "unit_loads", .kind = KeyKind::Other, .defaultText = "none", .meaning =
        R"md(record the contact loads on these bodies for `armour stress` (`<folder>/unit_loads/`, )md"
        R"md([output-files.md](output-files.md#unit-loads-unit_loads)): body names, or prefixes ending in `*` )md"
        R"md((`[unit_*]`; a prefix skips fixed bodies, a name of a fixed body is refused))md",
       .type = "list of names"},
      {.name = "unit_loads_interval", .num = {"s", kPositive, "0.02"}, .defaultText = show(d.unitLoadsInterval),
       .meaning =
        R"md(between unit-load records; each holds the step of its window at which the unit's contact force )md"
        R"md(was largest, so impacts are caught at any interval)md"},
      {.name = "unit_loads_cluster", .num = {"Dn", kFraction, "0.1"}, .defaultText = show(d.unitLoadsCluster),
       .meaning =
        R"md(the contact points of one other body within this width are recorded as one load (their sum, at )md"
        R"md(their normal-force-weighted centre))md"},
    });
  }();
  return table;
}

const Table& sleep() {
  static const Table table = [] {
    const simulation::SleepSettings d;
    return Table("sleep", {
      {.name = "enabled", .kind = KeyKind::Flag, .defaultText = show(d.enabled)},
      {.name = "scope", .kind = KeyKind::Choice,
       .defaultText = showChoice(kSleepScopes, static_cast<std::size_t>(d.scope)),
       .meaning =
        R"md(which bodies must be at rest for a body to sleep. `island`: every body of its contact island )md"
        R"md((Box2D's and Jolt's rule; one unit creeping anywhere in a pile keeps the whole pile awake). )md"
        R"md(`neighbours`: the body and the bodies it touches; a resting body next to a moving one stays )md"
        R"md(awake, one two contacts away may sleep and wakes as soon as a body it touches moves (ours; )md"
        R"md(measured in [benchmarks.md](benchmarks.md), "Sleeping by neighbours"))md",
       .choices = kSleepScopes},
      {.name = "linear_speed", .num = {"m/s", kNonNegative, "0.001"}, .defaultText = show(d.linearSpeed),
       .meaning = R"md(centroid speed below which a body may sleep)md"},
      {.name = "angular_speed", .num = {"rad/s", kNonNegative, "0.001"}, .defaultText = show(d.angularSpeed),
       .meaning = R"md(angular speed below which a body may sleep)md"},
      {.name = "time", .num = {"s", kNonNegative, "0.5"}, .defaultText = show(d.time),
       .meaning = R"md(both must hold this long)md"},
      {.name = "wake_load_fraction", .num = {"-", kPositive, "0.01 of the body's weight"},
       .defaultText = show(d.wakeLoadFraction), .meaning =
        R"md(a sleeping body wakes when its hydrodynamic load differs from the load it fell asleep under by )md"
        R"md(this fraction of its weight m g (a settled pack sleeps through still water and wakes when a wave )md"
        R"md(arrives))md"},
    });
  }();
  return table;
}

const Table& bodyDamping() {
  static const Table table = [] {
    const simulation::BodyDamping d;
    return Table("body_damping", {
      {.name = "linear", .num = {"1/s", kNonNegative, "0.9 (seed 001)"}, .defaultText = show(d.linear),
       .meaning = R"md(decay rate of the centroid velocity (seed 001: 0.9))md"},
      {.name = "angular", .num = {"1/s", kNonNegative, "0.9 (seed 001)"}, .defaultText = show(d.angular),
       .meaning = R"md(decay rate of the angular velocity (seed 001: 0.9))md"},
    });
  }();
  return table;
}

const std::vector<const Table*>& all() {
  static const std::vector<const Table*> list{&top(),    &materials(), &contact(),     &contactFdem(),
                                              &contactConstraint(), &output(), &sleep(), &bodyDamping()};
  return list;
}

} // namespace armour::io::tables

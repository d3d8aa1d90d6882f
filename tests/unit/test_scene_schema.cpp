// SPDX-License-Identifier: GPL-3.0-or-later
// The scene schema as data (issue 27): the generated key tables come from the settings structs'
// defaults and the reader's ranges, a document's tables are regenerated between their markers,
// and drift, missing tables and bad markers are reported.
#include "core/Error.hpp"
#include "io/Scene.hpp"
#include "io/SceneReader.hpp"
#include "io/SceneSchema.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace {

using armour::core::InputError;
using namespace armour::io;
namespace simulation = armour::simulation;

#define EXPECT_CONTAINS(text, fragment) \
  EXPECT_NE(std::string(text).find(fragment), std::string::npos) << "missing \"" << (fragment) << "\" in:\n" << (text)

const std::string kBody = "materials:\n  concrete: {density: 2400, friction: 0.6, restitution: 0.1}\nduration: 1\n"
                          "bodies:\n  - {shape: cube, dn: 1, material: concrete, position: [0, 0, 0.5]}\n";

std::string errorFrom(const std::string& yaml) {
  try {
    (void)parseScene(yaml, std::filesystem::current_path(), "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << yaml;
  return {};
}

std::string marked(const std::string& block, const std::string& body) {
  return "<!-- schema: " + block + " (generated) -->\n" + body + "<!-- end schema -->\n";
}

TEST(SceneSchema, TheTablesShowTheSettingsStructsDefaults) {
  // Every default in a table is printed from a default-constructed settings struct, so a changed
  // default changes the docs: these are the structs' values.
  const simulation::SleepSettings sleep;
  const std::string s = schemaTable("sleep");
  EXPECT_CONTAINS(s, fmt::format("| `linear_speed` | number >= 0 | m/s | {} |", sleep.linearSpeed));
  EXPECT_CONTAINS(s, fmt::format("| `time` | number >= 0 | s | {} |", sleep.time));
  const simulation::ConstraintSettings constraint;
  const std::string c = schemaTable("contact.constraint");
  EXPECT_CONTAINS(c, fmt::format("| `substeps` | integer 1 to 64 | - | {} |", constraint.substeps));
  EXPECT_CONTAINS(c, "| `friction_anchors` | true/false | | false |");
  EXPECT_CONTAINS(schemaTable("contact"), "| `solver` | `penalty` or `constraint` | | `penalty` |");
  EXPECT_CONTAINS(schemaTable("contact"), "| `max_overlap` | number in (0, 1] | Dn | 0.25 |");
  // Large round defaults as engineers write them (Material{}.penalty), and the top level's.
  EXPECT_CONTAINS(schemaTable("materials"), fmt::format("| `penalty` | number > 0 | Pa | 1e9 |"));
  EXPECT_EQ(Material{}.penalty, 1e9);
  EXPECT_CONTAINS(schemaTable("top"), "| `time_step_safety` | number in (0, 1] | - | 0.2 |");
  EXPECT_CONTAINS(schemaTable("top"), "| `gravity` | [x, y, z] | m/s^2 | [0, 0, -9.81] |");
  // Header, rule and one row per key.
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 2 + 6);
  EXPECT_THROW((void)schemaTable("sleeep"), InputError);
}

TEST(SceneSchema, TheReaderChecksKeysAndRangesFromTheSameTable) {
  // A key missing from the table is unknown to the reader; the table's range and unit word the error.
  EXPECT_CONTAINS(errorFrom(kBody + "sleep: {linear_sped: 0.01}\n"),
                  "sleep.linear_sped: unknown key (did you mean 'linear_speed'?); valid keys are: enabled, "
                  "scope, linear_speed, angular_speed, time, wake_load_fraction");
  EXPECT_CONTAINS(errorFrom(kBody + "sleep: {linear_speed: -1}\n"), "sleep.linear_speed = -1: must be >= 0 (unit: m/s)");
  EXPECT_CONTAINS(errorFrom(kBody + "contact: {max_overlap: 2}\n"), "contact.max_overlap = 2: must be in (0, 1] (unit: Dn)");
  EXPECT_CONTAINS(errorFrom(kBody + "contact: {solver: constrained}\n"),
                  "contact.solver = constrained: expected one of penalty, constraint (did you mean 'constraint'?)");
  EXPECT_CONTAINS(errorFrom(kBody + "contact: {solver: constraint, constraint: {substeps: 65}}\n"),
                  "contact.constraint.substeps = 65: at most 64 substeps; use a smaller time_step instead");
  EXPECT_CONTAINS(errorFrom(kBody + "time_step_safety: 0\n"), "time_step_safety = 0: must be in (0, 1] (unit: -)");
  EXPECT_CONTAINS(errorFrom("duration: 1\nmaterials:\n  rock: {density: -2650, friction: 0.6, restitution: 0.1}\n"),
                  "materials.rock.density = -2650: must be > 0 (unit: kg/m^3), e.g. 2400 for concrete, 2650 for rock");
  const Scene scene = parseScene(kBody + "sleep: {time: 2, scope: neighbours}\nbody_damping: {linear: 0.9}\n",
                                 std::filesystem::current_path(), "test.yaml");
  EXPECT_EQ(scene.sleep.time, 2.0);
  EXPECT_EQ(scene.sleep.scope, simulation::SleepScope::Neighbours);
  EXPECT_EQ(scene.sleep.linearSpeed, simulation::SleepSettings{}.linearSpeed);
  EXPECT_EQ(scene.bodyDamping.linear, 0.9);
}

TEST(SceneSchema, ADocumentsTablesAreRegeneratedBetweenTheirMarkers) {
  // Words about the markers inside a sentence are text, not markers.
  std::string doc = "# Scene file\n\nTables sit between `<!-- schema: BLOCK -->` and `<!-- end schema -->`.\n\n";
  for (const std::string& block : schemaBlocks()) doc += marked(block, schemaTable(block)) + "\nMore text.\n";
  // Current: nothing changes.
  const SchemaDocUpdate same = updateSchemaTables(doc, "doc.md");
  EXPECT_EQ(same.text, doc);
  EXPECT_TRUE(same.changed.empty());
  EXPECT_TRUE(same.missing.empty());
  // A hand edit of a default is drift: reported by block, and undone by the update.
  std::string edited = doc;
  const std::string row = fmt::format("| `time` | number >= 0 | s | {} |", simulation::SleepSettings{}.time);
  const std::size_t at = edited.find(row);
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, row.size(), "| `time` | number >= 0 | s | 0.25 |");
  const SchemaDocUpdate drift = updateSchemaTables(edited, "doc.md");
  EXPECT_EQ(drift.changed, std::vector<std::string>{"sleep"});
  EXPECT_EQ(drift.text, doc);
  // A block without its table is missing; the text around the others is kept.
  const std::string noSleep = "intro\n" + marked("contact", schemaTable("contact")) + "outro\n";
  const SchemaDocUpdate partial = updateSchemaTables(noSleep, "doc.md");
  EXPECT_EQ(partial.text, noSleep);
  EXPECT_EQ(partial.missing.size(), schemaBlocks().size() - 1);
  // Bad markers: an unknown block, and a table without its end marker, named with the line.
  try {
    (void)updateSchemaTables("a\n<!-- schema: slep -->\n<!-- end schema -->\n", "doc.md");
    ADD_FAILURE() << "no error for an unknown block";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "doc.md:2: no generated key table for block 'slep'");
  }
  try {
    (void)updateSchemaTables("<!-- schema: sleep -->\n| key |\n", "doc.md");
    ADD_FAILURE() << "no error for a missing end marker";
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), "doc.md:1: the generated table of 'sleep' has no end marker");
  }
}

} // namespace

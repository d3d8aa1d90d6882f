// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/SchemaCommands.hpp"

#include "core/TextFile.hpp"
#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "io/SceneSchema.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace armour::app {

namespace {

struct SchemaRequest {
  std::vector<std::string> blocks;
  std::string checkDoc;
  std::string updateDoc;
};

void runSchema(const SchemaRequest& r) {
  if (!r.checkDoc.empty() || !r.updateDoc.empty()) {
    const std::string path = r.checkDoc.empty() ? r.updateDoc : r.checkDoc;
    const io::SchemaDocUpdate u = io::updateSchemaTables(core::readTextFile(path, "the document (docs/scene-file.md)"), path);
    if (!u.missing.empty())
      core::failInput(path, "no generated table for {}; add a line '<!-- schema: BLOCK -->' and a line "
                            "'<!-- end schema -->' where each belongs, then run armour schema --update-doc {}",
                      fmt::join(u.missing, ", "), path);
    if (!r.updateDoc.empty()) {
      if (!u.changed.empty())
        core::writeFileAtomically(path, [&](std::ostream& out) { out << u.text; });
      fmt::print("{}: {} generated tables, {} updated{}\n", path, io::schemaBlocks().size(), u.changed.size(),
                 u.changed.empty() ? "" : fmt::format(" ({})", fmt::join(u.changed, ", ")));
      return;
    }
    if (!u.changed.empty())
      core::failInput(path, "the key tables of {} differ from the scene reader's schema (solver/io/SceneTables.cpp); "
                            "run: armour schema --update-doc {}",
                      fmt::join(u.changed, ", "), path);
    fmt::print("{}: the {} generated tables match the scene reader's schema\n", path, io::schemaBlocks().size());
    return;
  }
  const std::vector<std::string> blocks = r.blocks.empty() ? io::schemaBlocks() : r.blocks;
  for (std::size_t i = 0; i < blocks.size(); ++i)
    fmt::print("{}`{}`:\n\n{}", i == 0 ? "" : "\n", blocks[i], io::schemaTable(blocks[i]));
}

} // namespace

void addSchemaCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  auto r = std::make_shared<SchemaRequest>();
  auto* schema = app.add_subcommand("schema", "print the scene file's key tables (key, type, unit, default, meaning) "
                                              "from the schema the reader uses; check or update docs/scene-file.md");
  schema->add_option("blocks", r->blocks, "blocks to print, e.g. contact.constraint sleep (default: every block with "
                                          "a generated table)");
  auto* check = schema->add_option("--check-doc", r->checkDoc,
                                   "fail (exit 2) if this document's generated tables differ from the schema");
  schema->add_option("--update-doc", r->updateDoc, "rewrite this document's generated tables from the schema")
      ->excludes(check);
  schema->callback([r] { runSchema(*r); });
}

} // namespace armour::app

// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/SceneSchema.hpp"

#include "io/SceneTables.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace armour::io {

namespace {

constexpr std::string_view kBegin = "<!-- schema: ";
constexpr std::string_view kEnd = "<!-- end schema -->";

std::string row(const std::vector<std::string>& cells) {
  std::string line = "|";
  for (const std::string& c : cells) line += c.empty() ? " |" : fmt::format(" {} |", c);
  return line + "\n";
}

const schema::Table& tableAt(const std::string& path) {
  for (const schema::Table* t : tables::all())
    if (t->path() == path) return *t;
  throw core::InputError(fmt::format("no generated key table for block '{}'; the blocks with one are: {}", path,
                                     fmt::join(schemaBlocks(), ", ")));
}

} // namespace

std::vector<std::string> schemaBlocks() {
  std::vector<std::string> paths;
  for (const schema::Table* t : tables::all()) paths.push_back(t->path());
  return paths;
}

std::string schemaTable(const std::string& path) {
  const schema::Table& table = tableAt(path);
  std::string text = "| key | type | unit | default | meaning |\n|---|---|---|---|---|\n";
  for (const schema::Key& k : table.keys())
    text += row({fmt::format("`{}`", k.name), schema::typeText(k), std::string(k.num.unit), k.defaultText,
                 std::string(k.meaning)});
  return text;
}

SchemaDocUpdate updateSchemaTables(const std::string& document, const std::string& name) {
  SchemaDocUpdate out;
  std::vector<std::string> seen;
  std::size_t at = 0;
  while (true) {
    // A marker starts a line (the same words inside a sentence are text about the markers).
    std::size_t begin = document.find(kBegin, at);
    while (begin != std::string::npos && begin > 0 && document[begin - 1] != '\n')
      begin = document.find(kBegin, begin + 1);
    if (begin == std::string::npos) break;
    const std::size_t lineEnd = document.find('\n', begin);
    const std::size_t pathEnd = document.find_first_of(" \n", begin + kBegin.size());
    const std::string path = document.substr(begin + kBegin.size(), pathEnd - begin - kBegin.size());
    const std::size_t line = static_cast<std::size_t>(std::count(document.begin(), document.begin() + begin, '\n')) + 1;
    std::size_t end = document.find(kEnd, lineEnd);
    while (end != std::string::npos && document[end - 1] != '\n') end = document.find(kEnd, end + 1);
    if (lineEnd == std::string::npos || end == std::string::npos)
      throw core::InputError(fmt::format("{}:{}: the generated table of '{}' has no end marker '{}'; add it on the "
                                         "line after the table",
                                         name, line, path, kEnd));
    std::string generated;
    try {
      generated = schemaTable(path);
    } catch (const core::InputError& e) {
      throw core::InputError(fmt::format("{}:{}: {}", name, line, e.what()));
    }
    const std::string current = document.substr(lineEnd + 1, end - lineEnd - 1);
    if (current != generated) out.changed.push_back(path);
    seen.push_back(path);
    out.text += document.substr(at, lineEnd + 1 - at) + generated;
    at = end;
  }
  out.text += document.substr(at);
  for (const std::string& path : schemaBlocks())
    if (std::find(seen.begin(), seen.end(), path) == seen.end()) out.missing.push_back(path);
  return out;
}

} // namespace armour::io

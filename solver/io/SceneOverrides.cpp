// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/SceneOverrides.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cstddef>

namespace armour::io {
namespace {

/// One step of a key path: a map key, optionally followed by list indices (`static[0]`).
struct PathStep {
  std::string key;
  std::vector<std::size_t> indices;
};

std::vector<PathStep> parsePath(const std::string& set, const std::string& key) {
  std::vector<PathStep> steps;
  std::size_t start = 0;
  while (start <= key.size()) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    PathStep step;
    const std::size_t bracket = part.find('[');
    step.key = part.substr(0, bracket);
    if (step.key.empty())
      core::failInput("--set " + set, "the key path '{}' has an empty part; write it as block.key or list[0].key, "
                                      "e.g. hydro.storm.update_interval=0.5",
                      key);
    for (std::size_t at = bracket; at != std::string::npos;) {
      const std::size_t close = part.find(']', at);
      const std::string digits = close == std::string::npos ? std::string() : part.substr(at + 1, close - at - 1);
      bool number = !digits.empty();
      for (char c : digits) number = number && std::isdigit(static_cast<unsigned char>(c)) != 0;
      if (!number)
        core::failInput("--set " + set, "'{}': a list index is a whole number in brackets, e.g. static[0].friction",
                        part);
      step.indices.push_back(std::stoul(digits));
      at = close + 1 < part.size() ? close + 1 : std::string::npos;
      if (at != std::string::npos && part[at] != '[')
        core::failInput("--set " + set, "'{}': nothing may follow a list index but another index or a '.'", part);
    }
    steps.push_back(std::move(step));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return steps;
}

/// The value as YAML: a plain word or number stays a scalar without a source position (errors
/// then name the key, not a line of a file that does not hold it); a flow list or block is parsed.
YAML::Node parseValue(const std::string& set, const std::string& text) {
  if (!text.empty() && (text.front() == '[' || text.front() == '{')) {
    try {
      return YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      core::failInput("--set " + set, "the value '{}' is not valid YAML ({}); quote the whole option and check "
                                      "the brackets, e.g. --set 'gravity=[0, 0, -9.81]'",
                      text, e.msg);
    }
  }
  return YAML::Node(text);
}

void applyOne(YAML::Node& root, const std::string& set) {
  const std::size_t equals = set.find('=');
  if (equals == std::string::npos)
    core::failInput("--set " + set, "give KEY=VALUE, e.g. --set hydro.storm.update_interval=0.5");
  const std::string key = set.substr(0, equals);
  const std::string value = set.substr(equals + 1);
  if (value.empty())
    core::failInput("--set " + set, "the value is empty; give one (a key cannot be removed with --set: edit the "
                                    "scene file for that)");
  const std::vector<PathStep> steps = parsePath(set, key);
  // yaml-cpp nodes are handles: reassigning a handle would rebind it instead of walking the tree,
  // so the walk keeps one handle per level.
  std::vector<YAML::Node> chain{root};
  std::string walked;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const PathStep& step = steps[k];
    YAML::Node here = chain.back();
    if (here.IsScalar() || here.IsSequence())
      core::failInput("--set " + set, "'{}' is a single value or a list in the scene, not a block, so it has no key "
                                      "'{}'",
                      walked.empty() ? std::string("the scene") : walked, step.key);
    walked += (walked.empty() ? "" : ".") + step.key;
    const bool last = k + 1 == steps.size();
    if (step.indices.empty() && last) {
      here[step.key] = parseValue(set, value);
      break;
    }
    YAML::Node child = here[step.key];
    for (std::size_t i = 0; i < step.indices.size(); ++i) {
      const std::size_t index = step.indices[i];
      if (!child.IsSequence())
        core::failInput("--set " + set, "'{}' is not a list in the scene, so it has no item [{}]", walked, index);
      if (index >= child.size())
        core::failInput("--set " + set, "'{}' has {} items; give an index from 0 to {}", walked, child.size(),
                        child.size() - 1);
      walked += fmt::format("[{}]", index);
      if (last && i + 1 == step.indices.size()) {
        child[index] = parseValue(set, value);
        return;
      }
      child.reset(child[index]);
    }
    chain.push_back(child);
  }
}

} // namespace

void applyOverrides(YAML::Node& root, const std::vector<std::string>& sets) {
  if (sets.empty()) return;
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  for (const std::string& set : sets) applyOne(root, set);
}

std::string applyOverridesToText(const std::string& yaml, const std::vector<std::string>& sets,
                                 const std::string& sourceName) {
  if (sets.empty()) return yaml;
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    core::failInput(sourceName, "line {}: YAML syntax error: {}", e.mark.line + 1, e.msg);
  }
  applyOverrides(root, sets);
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

} // namespace armour::io

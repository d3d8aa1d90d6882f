// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file YamlSchema.hpp
/// The declarative schema helper of the scene reader (internal to SceneReader.cpp): a Block
/// reads one YAML mapping against its table of valid keys, refuses unknown or repeated keys
/// (suggesting the nearest valid one), and reads each value with its type, unit, range, default
/// and example, so every error names the file, line, key path, value and fix.

#include "core/Error.hpp"
#include "core/Log.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace armour::io::schema {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Where things are, and how errors are worded
// ---------------------------------------------------------------------------------------------

struct Context {
  std::string source;             ///< file name for messages
  std::filesystem::path baseDir;  ///< relative paths resolve here
  std::uint64_t seed = 1;         ///< the scene seed (default of the other seeds)
  std::vector<std::string>* warnings = nullptr;
};

inline std::string lineOf(const YAML::Mark& mark) { return mark.line >= 0 ? fmt::format(":{}", mark.line + 1) : ""; }

/// "scene.yaml:12: bodies[3].volume = -2: must be > 0 ..."; `subject` is the key path, with the
/// value when there is one.
[[noreturn]] inline void fail(const Context& c, const YAML::Mark& mark, const std::string& subject, const std::string& message) {
  // An empty subject is the top level of the file: its line says nothing, so it is left out.
  if (subject.empty()) throw core::InputError(fmt::format("{}: {}", c.source, message));
  throw core::InputError(fmt::format("{}{}: {}: {}", c.source, lineOf(mark), subject, message));
}

inline void warn(const Context& c, const YAML::Mark& mark, const std::string& subject, const std::string& message) {
  std::string text = fmt::format("{}{}: {}: {}", c.source, lineOf(mark), subject, message);
  core::logger("io")->warn("{}", text);
  if (c.warnings) c.warnings->push_back(std::move(text));
}

inline std::string child(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

inline std::string indexed(const std::string& path, std::size_t i) { return fmt::format("{}[{}]", path, i); }

/// The value as the user wrote it, on one line.
inline std::string valueText(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "(nothing)";
  if (node.IsScalar()) return node.Scalar();
  std::vector<std::string> parts;
  if (node.IsSequence()) {
    for (const auto& item : node) parts.push_back(valueText(item));
    return fmt::format("[{}]", fmt::join(parts, ", "));
  }
  for (const auto& kv : node) parts.push_back(fmt::format("{}: {}", valueText(kv.first), valueText(kv.second)));
  return fmt::format("{{{}}}", fmt::join(parts, ", "));
}

inline std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// " (did you mean 'x'?)" for a near miss, else "".
inline std::string suggestion(std::string_view word, const std::vector<std::string_view>& valid) {
  std::string_view best;
  std::size_t bestDistance = 3; // more than two edits is a different word, not a typo
  for (std::string_view v : valid) {
    const std::size_t d = editDistance(word, v);
    if (d < bestDistance) {
      bestDistance = d;
      best = v;
    }
  }
  return best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best);
}

// ---------------------------------------------------------------------------------------------
// The schema helper: one Block per YAML mapping, declared by its table of valid keys; each read
// states the key's type, unit, range and default, so a reader function reads as a table.
// ---------------------------------------------------------------------------------------------

/// Allowed interval of a number.
struct Range {
  double lo = -kInf;
  double hi = kInf;
  bool loOpen = false;
  bool hiOpen = false;
  [[nodiscard]] bool contains(double v) const {
    return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
  }
  [[nodiscard]] std::string text() const {
    if (hi == kInf) return fmt::format("{} {}", loOpen ? ">" : ">=", lo);
    if (lo == -kInf) return fmt::format("{} {}", hiOpen ? "<" : "<=", hi);
    return fmt::format("in {}{}, {}{}", loOpen ? "(" : "[", lo, hi, hiOpen ? ")" : "]");
  }
};

constexpr Range kAnyNumber{};
constexpr Range kPositive{0.0, kInf, true, false};
constexpr Range kNonNegative{0.0, kInf, false, false};
constexpr Range kUnitInterval{0.0, 1.0, false, false};
constexpr Range kFraction{0.0, 1.0, true, false}; // (0, 1]

/// A number's meaning for messages: unit, range, and an example of a good value.
struct Num {
  std::string_view unit;
  Range range = kAnyNumber;
  std::string_view example = {};
};

inline std::string unitText(std::string_view unit) { return fmt::format("unit: {}", unit); }

inline std::string fixText(const Num& n) {
  return n.example.empty() ? fmt::format("({})", unitText(n.unit))
                           : fmt::format("({}), e.g. {}", unitText(n.unit), n.example);
}

using KeyList = std::vector<std::string_view>;

/// True for a decimal number beyond the range of a double, such as 1e999: strtod reads all of it
/// and overflows (yaml-cpp then reports only that the scalar is not a double). A number too small
/// for a double (1e-999) reads as 0, as it does in every other tool.
inline bool overflowsDouble(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && errno == ERANGE && std::isinf(v);
}

// ---------------------------------------------------------------------------------------------
// The schema as data: a Table per block lists its keys with type, unit, range, default and
// meaning. It drives the Block's key check and its reads' messages, and generates the key tables
// of docs/scene-file.md (io/SceneSchema.hpp; `armour schema`).
// ---------------------------------------------------------------------------------------------

enum class KeyKind {
  Number,  ///< a number with unit and range (Key::num)
  Integer, ///< a whole number in [intMin, intMax]
  Flag,    ///< true or false
  Choice,  ///< one of Key::choices
  Other,   ///< text, lists, mappings: Key::type says what
};

/// One key of a block.
struct Key {
  std::string_view name;
  KeyKind kind = KeyKind::Number;
  Num num{};                    ///< unit (every kind), range and example (numbers)
  std::string defaultText{};    ///< the default as the docs show it, from the settings struct; empty: none
  std::string_view meaning{};   ///< the docs' meaning column (markdown)
  KeyList choices{};            ///< KeyKind::Choice, in the order of their enum
  std::uint64_t intMin = 0;     ///< KeyKind::Integer
  std::uint64_t intMax = std::numeric_limits<std::uint64_t>::max();
  std::string_view type{};      ///< the docs' type column where the kind's own does not say enough
  std::string_view intWhat{};   ///< KeyKind::Integer: what the number counts, for messages
  std::string_view overMax{};   ///< KeyKind::Integer: the rest of "at most <intMax> ...", with the fix
};

/// The default of a number as the docs show it ("0.001", "3", "1e-06").
inline std::string show(double v) {
  // Large round numbers as engineers write them: 1e9, not 1000000000.
  if (std::abs(v) >= 1e6 && v == std::round(v)) {
    // "{:e}" of a round number: mantissa digits, then the exponent, e.g. 1.000000e+09.
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(v))));
    return fmt::format("{}e{}", v / std::pow(10.0, exponent), exponent);
  }
  return fmt::format("{}", v);
}
inline std::string show(bool v) { return v ? "true" : "false"; }

/// A block's keys, in the order the docs list them.
class Table {
public:
  Table(std::string path, std::vector<Key> keys) : path_(std::move(path)), keys_(std::move(keys)) {
    for (const Key& k : keys_) names_.push_back(k.name);
  }
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::vector<Key>& keys() const { return keys_; }
  [[nodiscard]] const KeyList& names() const { return names_; }
  [[nodiscard]] const Key* find(std::string_view name) const {
    for (const Key& k : keys_)
      if (k.name == name) return &k;
    return nullptr;
  }

private:
  std::string path_;
  std::vector<Key> keys_;
  KeyList names_;
};

/// The docs' type column of a key: "number >= 0", "integer 1 to 64", "true/false", "`a` or `b`".
inline std::string typeText(const Key& k) {
  if (!k.type.empty()) return std::string(k.type);
  switch (k.kind) {
  case KeyKind::Number: return k.num.range.lo == -kInf && k.num.range.hi == kInf ? "number" : "number " + k.num.range.text();
  case KeyKind::Integer:
    return k.intMax == std::numeric_limits<std::uint64_t>::max() ? fmt::format("integer >= {}", k.intMin)
                                                                 : fmt::format("integer {} to {}", k.intMin, k.intMax);
  case KeyKind::Flag: return "true/false";
  case KeyKind::Choice: {
    std::string text;
    for (std::size_t i = 0; i < k.choices.size(); ++i)
      text += fmt::format("{}`{}`", i == 0 ? "" : i + 1 == k.choices.size() ? " or " : ", ", k.choices[i]);
    return text;
  }
  case KeyKind::Other: break;
  }
  return "";
}

class Block {
public:
  /// Check that `node` is a mapping whose keys are all in `table` (and not repeated); the reads
  /// that name no unit or range take them from the table.
  Block(const Context& ctx, const YAML::Node& node, const Table& table) : Block(ctx, node, table.path(), table.names()) {
    table_ = &table;
  }
  /// The same under another path (a table shared by several blocks, or an indexed item).
  Block(const Context& ctx, const YAML::Node& node, std::string path, const Table& table)
      : Block(ctx, node, std::move(path), table.names()) {
    table_ = &table;
  }
  /// Check that `node` is a mapping whose keys are all in `keys` (and not repeated).
  Block(const Context& ctx, const YAML::Node& node, std::string path, const KeyList& keys)
      : ctx_(ctx), node_(node), path_(std::move(path)), keys_(keys) {
    if (node_.IsNull()) return; // "contact:" with nothing under it: all defaults
    if (!node_.IsMap())
      fail(ctx_, node_.Mark(), path_.empty() ? "" : fmt::format("{} = {}", path_, valueText(node_)),
           fmt::format("expected a mapping of key: value{}; valid keys are: {}",
                       path_.empty() ? fmt::format(" at the top of the file, found '{}'", valueText(node_)) : "",
                       fmt::join(keys_, ", ")));
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      const std::string key = kv.first.Scalar();
      if (std::find(keys_.begin(), keys_.end(), key) == keys_.end())
        fail(ctx_, kv.first.Mark(), child(path_, key),
             fmt::format("unknown key{}; valid keys are: {}", suggestion(key, keys_), fmt::join(keys_, ", ")));
      if (!seen.insert(key).second)
        fail(ctx_, kv.first.Mark(), child(path_, key), "key given twice; keep one");
    }
  }

  [[nodiscard]] const Context& context() const { return ctx_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::string path(std::string_view key) const { return child(path_, key); }
  [[nodiscard]] YAML::Mark mark() const { return node_.Mark(); }
  [[nodiscard]] bool has(std::string_view key) const { return node_.IsMap() && get(key).IsDefined(); }
  /// The value under `key` (undefined if absent). Const access: a non-const operator[] would add
  /// the key to the document.
  [[nodiscard]] YAML::Node get(std::string_view key) const {
    assertDeclared(key);
    const YAML::Node& node = node_;
    return node[std::string(key)];
  }
  [[nodiscard]] YAML::Mark mark(std::string_view key) const { return has(key) ? get(key).Mark() : node_.Mark(); }

  [[noreturn]] void failValue(std::string_view key, const std::string& message) const {
    fail(ctx_, mark(key), fmt::format("{} = {}", path(key), valueText(get(key))), message);
  }
  [[noreturn]] void failMissing(std::string_view key, const std::string& what) const {
    fail(ctx_, node_.Mark(), path_, fmt::format("missing key '{}': {}", key, what));
  }
  void warnValue(std::string_view key, const std::string& message) const {
    warn(ctx_, mark(key), fmt::format("{} = {}", path(key), valueText(get(key))), message);
  }

  /// A number; `fallback` unset makes the key required.
  [[nodiscard]] double number(std::string_view key, const Num& n, std::optional<double> fallback = {}) const {
    if (!has(key)) {
      if (fallback) return *fallback;
      failMissing(key, fmt::format("a number {}", fixText(n)));
    }
    return toNumber(key, get(key), path(key), n);
  }
  [[nodiscard]] std::optional<double> optionalNumber(std::string_view key, const Num& n) const {
    if (!has(key)) return std::nullopt;
    return number(key, n);
  }

  /// A number whose unit, range and example are the table's.
  [[nodiscard]] double number(std::string_view key, std::optional<double> fallback = {}) const {
    return number(key, tableKey(key, KeyKind::Number).num, fallback);
  }
  /// An integer within the table's bounds.
  [[nodiscard]] std::uint64_t integer(std::string_view key, std::optional<std::uint64_t> fallback = {}) const {
    const Key& k = tableKey(key, KeyKind::Integer);
    const std::uint64_t v = integer(key, k.intMin, k.intWhat, fallback);
    if (v > k.intMax) failValue(key, fmt::format("at most {} {}", k.intMax, k.overMax));
    return v;
  }
  /// One of the table's choices, as its index.
  [[nodiscard]] std::size_t choice(std::string_view key, std::optional<std::size_t> fallback = {}) const {
    return choice(key, tableKey(key, KeyKind::Choice).choices, fallback);
  }

  /// A list of `count` numbers, each checked against n.range.
  [[nodiscard]] std::vector<double> numbers(std::string_view key, std::size_t count, const Num& n,
                                            std::optional<std::vector<double>> fallback = {}) const {
    if (!has(key)) {
      if (fallback) return *fallback;
      failMissing(key, fmt::format("a list of {} numbers {}", count, fixText(n)));
    }
    const YAML::Node list = get(key);
    if (!list.IsSequence() || list.size() != count)
      failValue(key, fmt::format("expected a list of {} numbers {}", count, fixText(n)));
    std::vector<double> values;
    for (std::size_t i = 0; i < count; ++i) values.push_back(toNumber(key, list[i], indexed(path(key), i), n));
    return values;
  }
  [[nodiscard]] Vec3 vec3(std::string_view key, const Num& n, std::optional<Vec3> fallback = {}) const {
    if (!has(key) && fallback) return *fallback;
    const std::vector<double> v = numbers(key, 3, n);
    return {v[0], v[1], v[2]};
  }

  [[nodiscard]] std::string text(std::string_view key, std::string_view what, std::optional<std::string> fallback = {}) const {
    if (!has(key)) {
      if (fallback) return *fallback;
      failMissing(key, std::string(what));
    }
    const YAML::Node value = get(key);
    if (!value.IsScalar() || value.Scalar().empty()) failValue(key, fmt::format("expected {}", what));
    return value.Scalar();
  }

  /// One of `choices`, returned as its index.
  [[nodiscard]] std::size_t choice(std::string_view key, const KeyList& choices, std::optional<std::size_t> fallback = {}) const {
    const std::string what = fmt::format("one of {}", fmt::join(choices, ", "));
    const std::string value = text(key, what, fallback ? std::optional<std::string>(std::string(choices[*fallback])) : std::nullopt);
    const auto found = std::find(choices.begin(), choices.end(), value);
    if (found == choices.end()) failValue(key, fmt::format("expected {}{}", what, suggestion(value, choices)));
    return static_cast<std::size_t>(found - choices.begin());
  }

  [[nodiscard]] bool flag(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    bool value = false;
    if (!get(key).IsScalar() || !YAML::convert<bool>::decode(get(key), value)) failValue(key, "expected true or false");
    return value;
  }

  /// A non-negative integer (counts, seeds), parsed exactly (no rounding through double).
  [[nodiscard]] std::uint64_t integer(std::string_view key, std::uint64_t minimum, std::string_view what,
                                      std::optional<std::uint64_t> fallback = {}) const {
    if (!has(key)) {
      if (fallback) return *fallback;
      failMissing(key, fmt::format("an integer >= {} ({})", minimum, what));
    }
    return toInteger(key, get(key), path(key), minimum, what);
  }
  [[nodiscard]] std::vector<std::uint64_t> integers(std::string_view key, std::size_t count, std::uint64_t minimum,
                                                    std::string_view what) const {
    if (!has(key)) failMissing(key, fmt::format("a list of {} integers >= {} ({})", count, minimum, what));
    const YAML::Node list = get(key);
    if (!list.IsSequence() || list.size() != count)
      failValue(key, fmt::format("expected a list of {} integers >= {} ({})", count, minimum, what));
    std::vector<std::uint64_t> values;
    for (std::size_t i = 0; i < count; ++i) values.push_back(toInteger(key, list[i], indexed(path(key), i), minimum, what));
    return values;
  }

  /// Exactly one (or, if `optional`, at most one) of `keys` is present; returns its index or -1.
  int oneOf(const KeyList& alternatives, bool optional, std::string_view what) const {
    std::vector<std::string_view> present;
    int index = -1;
    for (std::size_t i = 0; i < alternatives.size(); ++i) {
      if (has(alternatives[i])) {
        present.push_back(alternatives[i]);
        index = static_cast<int>(i);
      }
    }
    const auto quoted = [](const KeyList& list) {
      std::vector<std::string> q;
      for (auto k : list) q.push_back(fmt::format("'{}'", k));
      return fmt::format("{}", fmt::join(q, " or "));
    };
    if (present.size() > 1)
      fail(ctx_, mark(present[1]), path_,
           fmt::format("give only one of {} ({}); found {}", quoted(alternatives), what, quoted(present)));
    if (present.empty() && !optional)
      fail(ctx_, node_.Mark(), path_, fmt::format("give one of {} ({})", quoted(alternatives), what));
    return index;
  }

  void refuse(std::string_view key, std::string_view why) const {
    if (has(key)) fail(ctx_, mark(key), path(key), std::string(why));
  }

private:
  const Key& tableKey(std::string_view key, KeyKind kind) const {
    const Key* k = table_ ? table_->find(key) : nullptr;
    if (!k || k->kind != kind)
      throw std::logic_error(fmt::format("scene schema: key '{}' of {} read without its table entry", key, path_));
    return *k;
  }

  void assertDeclared([[maybe_unused]] std::string_view key) const {
    // A read of an undeclared key is a programming error: it would never be reachable by the user.
    if (std::find(keys_.begin(), keys_.end(), key) == keys_.end())
      throw std::logic_error(fmt::format("scene schema: key '{}' read but not declared in {}", key, path_));
  }

  double toNumber(std::string_view key, const YAML::Node& value, const std::string& valuePath, const Num& n) const {
    const auto bad = [&](const std::string& message) {
      fail(ctx_, value.IsDefined() ? value.Mark() : mark(key), fmt::format("{} = {}", valuePath, valueText(value)), message);
    };
    if (!value.IsScalar()) bad(fmt::format("expected a number {}", fixText(n)));
    double v = 0.0;
    if (!YAML::convert<double>::decode(value, v)) {
      std::string lower = value.Scalar();
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
      const bool nonFinite = lower == "nan" || lower == "inf" || lower == "-inf" || lower == "+inf" || lower == "infinity";
      if (overflowsDouble(value.Scalar()))
        bad(fmt::format("out of range: beyond {:.6g}, the largest number a double holds; give a value of this "
                        "key's size {}",
                        std::numeric_limits<double>::max(), fixText(n)));
      bad(fmt::format("{} {}", nonFinite ? "must be a finite number" : "expected a number", fixText(n)));
    }
    if (!std::isfinite(v)) bad(fmt::format("must be a finite number {}", fixText(n)));
    if (!n.range.contains(v)) bad(fmt::format("must be {} {}", n.range.text(), fixText(n)));
    return v;
  }

  std::uint64_t toInteger(std::string_view key, const YAML::Node& value, const std::string& valuePath,
                          std::uint64_t minimum, std::string_view what) const {
    const auto bad = [&]() {
      fail(ctx_, value.IsDefined() ? value.Mark() : mark(key), fmt::format("{} = {}", valuePath, valueText(value)),
           fmt::format("expected an integer >= {} ({})", minimum, what));
    };
    if (!value.IsScalar()) bad();
    const std::string& s = value.Scalar();
    std::uint64_t v = 0;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (error != std::errc() || end != s.data() + s.size() || v < minimum) bad();
    return v;
  }

  const Context& ctx_;
  YAML::Node node_;
  std::string path_;
  const KeyList& keys_;
  const Table* table_ = nullptr;
};

} // namespace armour::io::schema

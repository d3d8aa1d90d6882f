// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/JsonWriter.hpp"

#include <fmt/format.h>

#include <cmath>

namespace armour::core {

std::string jsonString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
    case '"':
      out += "\\\"";
      break;
    case '\\':
      out += "\\\\";
      break;
    case '\n':
      out += "\\n";
      break;
    case '\t':
      out += "\\t";
      break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) {
        out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
      } else {
        out += c;
      }
    }
  }
  return out + "\"";
}

std::string jsonNumber(double value) { return std::isfinite(value) ? fmt::format("{}", value) : std::string("null"); }

} // namespace armour::core

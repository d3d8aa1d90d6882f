// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file JsonWriter.hpp
/// The values of the JSON files armour writes (`armour report`'s summary.json, `armour storm-file
/// info --json`, the placement summary): strings escaped per RFC 8259 section 7 and numbers in
/// their shortest round-trip form. The files lay out their own objects; these give the values.

#include <string>
#include <string_view>

namespace armour::core {

/// `text` as a JSON string literal: quotes and backslashes escaped, newline and tab as \n and \t,
/// every other control character (U+0000 to U+001F) as \u00XX. Other bytes (UTF-8 included) are
/// copied as they are.
[[nodiscard]] std::string jsonString(std::string_view text);

/// A number as JSON: the shortest text that reads back to the same double; `null` for a NaN or an
/// infinity, which JSON cannot hold.
[[nodiscard]] std::string jsonNumber(double value);

} // namespace armour::core

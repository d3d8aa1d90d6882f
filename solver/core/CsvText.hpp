// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file CsvText.hpp
/// The text of the CSV files armour writes and reads (final_state.csv, unit_loads/*.csv): a field
/// quoted when it holds a comma, a quote or a newline (RFC 4180, quotes doubled), and a line split
/// back into its fields; and a name made safe for a file name.

#include <string>
#include <vector>

namespace armour::core {

/// `text` as one CSV field: as it is, or in quotes with its quotes doubled when it holds ',', '"'
/// or a newline.
[[nodiscard]] std::string csvField(const std::string& text);

/// The fields of one CSV line: quoted fields unquoted ("" read as "), '\r' dropped.
[[nodiscard]] std::vector<std::string> splitCsvLine(const std::string& line);

/// `name` with every character other than [A-Za-z0-9_.-] replaced by '_', for a file name.
[[nodiscard]] std::string fileSafeName(const std::string& name);

} // namespace armour::core

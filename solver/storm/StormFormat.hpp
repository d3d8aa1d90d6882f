// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file StormFormat.hpp
/// Internal to the storm file (not installed, not included by StormFile.hpp): what the writer
/// (StormWriter.cpp) and the reader (StormReader.cpp) share about the layout of docs/storm-file.md:
/// the voxel data variables with their names and units, the unit spellings a reader accepts, the
/// alpha round-off tolerance and the header checks both run (the writer on the header given, the
/// reader on the header read). StormFile.hpp stays plain C++11 for foam-bridge; this header is C++20.

#include "storm/StormFile.hpp"

#include <string>
#include <vector>

namespace armour::storm::detail {

/// alpha outside [0, 1] by less than this is VOF round-off and is clamped; more is an error.
inline constexpr double kAlphaTolerance = 1e-6;

/// The voxel data variables in file order. v is optional (header.hasVelocityY).
struct DataVariableInfo {
  const char* name;
  const char* units;
  const char* standardName; ///< nullptr: none in the CF table
  const char* longName;
};
inline constexpr int kDataVariables = 5;
inline constexpr int kP = 0, kU = 1, kV = 2, kW = 3, kAlpha = 4;
inline constexpr DataVariableInfo kDataInfo[kDataVariables] = {
    {"p", "Pa", "sea_water_pressure_due_to_sea_water", "total pressure (hydrostatic + dynamic), gauge"},
    {"u", "m s-1", "sea_water_x_velocity", "velocity along x (onshore)"},
    {"v", "m s-1", "sea_water_y_velocity", "velocity along y (along the trunk)"},
    {"w", "m s-1", "upward_sea_water_velocity", "velocity along z (up)"},
    {"alpha", "1", nullptr, "water volume fraction (0 air, 1 water)"},
};

/// The array of data variable `variable` (kP ... kAlpha) in a record.
const std::vector<double>& recordArray(const StormRecord& r, int variable);
std::vector<double>& recordArray(StormRecord& r, int variable);

/// Unit spellings a reader accepts besides the canonical one written (docs/storm-file.md, "Units").
const std::vector<std::string>& acceptedUnits(const std::string& canonical);

/// Field names of the header checks: the C++ field for the writer, the netCDF name for the reader.
struct Naming {
  bool inFile;
  std::string operator()(const std::string& code, const std::string& file) const { return inFile ? file : code; }
};

/// The checks of the variability model (Variability::present false: none).
void validateVariability(const std::string& where, const Variability& v, const Naming& name);
/// The checks shared by the writer (on the header given) and the reader (on the header read).
void validateHeader(const std::string& where, const StormHeader& h, const Naming& name);

} // namespace armour::storm::detail

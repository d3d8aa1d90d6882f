// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file RunScene.hpp
/// The scene a run was made from, as the run read it, found from its bodies.nc (BodySeriesReader):
/// the scene file it names, read again with the run's --set changes and, for a storm replay, the
/// storm settings the run was given on its command line. `armour report` reads a run this way.

#include "io/BodySeriesReader.hpp"
#include "io/Scene.hpp"

#include <filesystem>

namespace armour::io {

/// The scene file of the run in `runDir`: bodies.nc's `scene_file`, else (files of older runs)
/// the argument after `run` or `storm` on the last line of the history attribute that has one;
/// looked for as recorded, relative to the current folder and to the run folder's parent (a moved
/// run). Throws core::InputError naming bodies.nc and the fix (--scene) when none is found.
[[nodiscard]] std::filesystem::path sceneFileOfRun(const BodySeriesReader& series, const std::filesystem::path& runDir);

/// The scene as the run read it: with the run's --set changes (`scene_sets`) and, for a storm
/// replay, the storm settings it ran with (`armour storm --storm --time-offset`: storm_file,
/// storm_time_offset, storm_offset_x/z, storm_ramp_time, hydro_bodies).
[[nodiscard]] Scene sceneOfRun(const std::filesystem::path& scenePath, const BodySeriesReader& series);

} // namespace armour::io

// SPDX-License-Identifier: GPL-3.0-or-later
/// The `armour` program: one entry point, one subcommand per job.

#include "app/AnalyseCommands.hpp"
#include "app/CommandContext.hpp"
#include "app/DeformCommands.hpp"
#include "app/StressCommands.hpp"
#include "app/EnsembleCommands.hpp"
#include "app/PlaceCommands.hpp"
#include "app/ReportCommands.hpp"
#include "app/RunCommands.hpp"
#include "app/SchemaCommands.hpp"
#include "app/ShapeCommands.hpp"
#include "app/StormCommands.hpp"
#include "core/BuildInfo.hpp"
#include "core/Error.hpp"
#include "io/Scene.hpp" // armour::io::Vec3, which the schema header expects
#include "io/YamlSchema.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <limits>

namespace {

/// CLI11 reads a number beyond the range of a double (`--duration 1e999`) as infinity, which the
/// commands then refuse as "inf"; say instead that the number as typed is out of range, as the
/// scene reader does for the same number in a file or a --set (io::schema::overflowsDouble).
void refuseOutOfRangeNumbers(CLI::App& app) {
  const CLI::Validator inRange(
      [](std::string& value) -> std::string {
        if (!armour::io::schema::overflowsDouble(value)) return {};
        return fmt::format("{} is out of range: beyond {:.6g}, the largest number a double holds; give an ordinary "
                           "number",
                           value, std::numeric_limits<double>::max());
      },
      "", "in the range of a double");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_name() == "FLOAT") option->check(inRange);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) refuseOutOfRangeNumbers(*sub);
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"armour: breakwater armour-layer stability toolchain (wave tank -> storm file -> rigid FDEM)"};
  app.require_subcommand(1);
  armour::app::GlobalOptions global;
  app.add_option("--log-level", global.logLevel, "log level: trace, debug, info, warn, error, off")
      ->capture_default_str();
  app.add_option("--log-file", global.logFile, "also write the run log to this file");
  app.set_version_flag("--version", armour::core::buildInfo());

  app.add_subcommand("version", "print the version and build information (git hash, compiler, OpenMP threads)")
      ->callback([] { std::cout << armour::core::buildInfo() << "\n"; });
  armour::app::addShapeCommands(app, global);
  armour::app::addRunCommands(app, global);
  armour::app::addStormCommands(app, global);
  armour::app::addPlaceCommands(app, global);
  armour::app::addAnalyseCommands(app, global);
  armour::app::addEnsembleCommands(app, global);
  armour::app::addReportCommands(app, global);
  armour::app::addDeformCommands(app, global);
  armour::app::addStressCommands(app, global);
  armour::app::addSchemaCommands(app, global);

  refuseOutOfRangeNumbers(app);

  std::string commandLine;
  for (int i = 0; i < argc; ++i) {
    commandLine += (i ? " " : "") + std::string(argv[i]);
  }
  app.parse_complete_callback([&] { armour::app::startRun(global, commandLine); });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const armour::core::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "internal error: " << e.what() << "\n(please report this with the command line)\n";
    return 3;
  }
  return 0;
}

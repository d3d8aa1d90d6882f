// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/ReportCommands.hpp"

namespace armour::app {

void addReportCommands(CLI::App& /*app*/, GlobalOptions& /*global*/) {}

} // namespace armour::app

// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/TextFile.hpp"

#include "core/Error.hpp"

#include <fstream>
#include <sstream>

namespace armour::core {

std::string readTextFile(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot open {} (looked for {})", path.string(), what,
                                 std::filesystem::absolute(path).lexically_normal().string()));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace armour::core

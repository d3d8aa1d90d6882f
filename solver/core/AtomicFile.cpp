// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/AtomicFile.hpp"

#include "core/Error.hpp"

#include <fstream>
#include <system_error>
#include <unistd.h>

namespace armour::core {

std::filesystem::path temporarySibling(const std::filesystem::path& path) {
  auto tmp = path;
  tmp += fmt::format(".tmp.{}", static_cast<long>(::getpid()));
  return tmp;
}

void commitAtomicFile(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    failInput(path.string(), "cannot move the finished file into place ({}); check the folder permissions",
              ec.message());
  }
}

void writeFileAtomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
                         bool binary) {
  const auto tmp = temporarySibling(path);
  {
    std::ofstream out(tmp, binary ? std::ios::binary : std::ios::out);
    if (!out) {
      failInput(path.string(), "cannot open for writing; check that the folder '{}' exists and is writable",
                path.parent_path().empty() ? "." : path.parent_path().string());
    }
    write(out);
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      failInput(path.string(), "write failed (disk full?); nothing was written");
    }
  }
  commitAtomicFile(tmp, path);
}

} // namespace armour::core

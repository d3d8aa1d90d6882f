// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Hash.hpp
/// The 64-bit FNV-1a hash (Fowler, Noll, Vo), to tell a checkpoint's setup from an edited one.
/// Not a security measure.

#include <cstdint>
#include <string_view>

namespace armour::core {

inline constexpr std::uint64_t kFnv1aOffset = 14695981039346656037ull;
inline constexpr std::uint64_t kFnv1aPrime = 1099511628211ull;

/// FNV-1a of `bytes`, continuing from `h` (the offset basis for a new hash).
[[nodiscard]] inline std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = kFnv1aOffset) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnv1aPrime;
  }
  return h;
}

} // namespace armour::core

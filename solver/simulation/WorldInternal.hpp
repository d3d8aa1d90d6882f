// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file WorldInternal.hpp
/// Shared by the World's source files (World.cpp and the World*.cpp of its stages) and nothing
/// else: not installed, not included by any public header. It holds the flag bits that tell the
/// kinds of contact pair and of sample key apart. They are also the contact_second and
/// contact_key values of a checkpoint (CheckpointFile.cpp documents them in the file), so
/// changing them breaks existing checkpoints.

#include <cstdint>

namespace armour::simulation::detail {

constexpr std::uint32_t kPlaneBit = 0x80000000u;  ///< second pair index of a body-plane pair
constexpr std::uint32_t kConvexBit = 0x40000000u; ///< second pair index of a body-convex pair
constexpr std::uint32_t kStaticBits = kPlaneBit | kConvexBit;
constexpr std::uint32_t kReverseBit = 0x80000000u; ///< sample key: B's samples in A (contact::kReverseSampleBit)

} // namespace armour::simulation::detail

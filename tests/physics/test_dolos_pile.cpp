// SPDX-License-Identifier: GPL-3.0-or-later
// placeholder: being written
#include <gtest/gtest.h>
TEST(Placeholder, Pending) { GTEST_SKIP(); }

// SPDX-License-Identifier: GPL-3.0-or-later
// core::jsonString and core::jsonNumber (core/JsonWriter.hpp): strings escaped per RFC 8259
// section 7 (quote, backslash and every control character U+0000..U+001F; nothing else), numbers
// in their shortest round-trip form, null for what JSON cannot hold.

#include "core/JsonWriter.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

using armour::core::jsonNumber;
using armour::core::jsonString;

TEST(JsonWriter, PlainTextIsQuotedUnchanged) {
  EXPECT_EQ(jsonString(""), "\"\"");
  EXPECT_EQ(jsonString("wave-slope/run 1"), "\"wave-slope/run 1\"");
  // Bytes of UTF-8 and DEL need no escape (RFC 8259: only U+0000..U+001F, quote and backslash).
  EXPECT_EQ(jsonString("Dn \xc2\xb1 1 \x7f"), "\"Dn \xc2\xb1 1 \x7f\"");
}

TEST(JsonWriter, QuotesAndBackslashesAreEscaped) {
  EXPECT_EQ(jsonString("a \"b\" c"), "\"a \\\"b\\\" c\"");
  EXPECT_EQ(jsonString("C:\\runs\\"), "\"C:\\\\runs\\\\\"");
  EXPECT_EQ(jsonString("\\\""), "\"\\\\\\\"\"");
}

TEST(JsonWriter, ControlCharactersAreEscapedNotDropped) {
  EXPECT_EQ(jsonString("one\ntwo"), "\"one\\ntwo\"");
  EXPECT_EQ(jsonString("a\tb"), "\"a\\tb\"");
  EXPECT_EQ(jsonString("cr\r"), "\"cr\\u000d\"");
  EXPECT_EQ(jsonString("\x01\x1f"), "\"\\u0001\\u001f\"");
  EXPECT_EQ(jsonString("\b\f"), "\"\\u0008\\u000c\"");
  EXPECT_EQ(jsonString(std::string("nul\0end", 7)), "\"nul\\u0000end\"");
  // No raw control character is left in the literal.
  std::string all;
  for (int c = 0; c < 0x20; ++c) all += static_cast<char>(c);
  const std::string escaped = jsonString(all);
  for (const char c : escaped) EXPECT_GE(static_cast<unsigned char>(c), 0x20) << "raw control character left";
  EXPECT_EQ(escaped.size(), 2u + 30u * 6u + 2u * 2u); // 30 as \u00XX, newline and tab as \n and \t
}

TEST(JsonWriter, NumbersRoundTripAndNonFiniteIsNull) {
  EXPECT_EQ(jsonNumber(0.1), "0.1");
  EXPECT_EQ(jsonNumber(1.0), "1");
  EXPECT_EQ(jsonNumber(-2.5e-7), "-2.5e-07");
  EXPECT_EQ(std::stod(jsonNumber(1.0 / 3.0)), 1.0 / 3.0);
  EXPECT_EQ(jsonNumber(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(jsonNumber(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(jsonNumber(-std::numeric_limits<double>::infinity()), "null");
}

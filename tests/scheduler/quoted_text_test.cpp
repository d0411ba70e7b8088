// Caller-sent text in error messages and logs: quoted, escaped and bounded.
#include "scheduler/quoted_text.h"

#include <gtest/gtest.h>

namespace pathfarm::farm {
namespace {

TEST(QuotedText, PrintableTextStaysAndTheRestIsEscaped) {
  EXPECT_EQ(quotedInput("dui"), "\"dui\"");
  EXPECT_EQ(quotedInput(""), "\"\"");
  EXPECT_EQ(quotedInput("a\nb"), "\"a\\x0ab\"");  // no forged log line
  EXPECT_EQ(quotedInput("say \"hi\"\\"), "\"say \\x22hi\\x22\\x5c\"");
  EXPECT_EQ(quotedInput(std::string("\0\x7f\xff", 3)), "\"\\x00\\x7f\\xff\"");
}

TEST(QuotedText, LongTextIsCutAndCounted) {
  const std::string text(kQuotedBytes + 1000, 'x');
  EXPECT_EQ(quotedInput(text), "\"" + std::string(kQuotedBytes, 'x') + "\" (1000 more bytes)");
}

}  // namespace
}  // namespace pathfarm::farm

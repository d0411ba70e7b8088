// Caller-sent text in error messages and logs: quoted, escaped and bounded.
#include "scheduler/quoted_text.h"

#include <gtest/gtest.h>

#include "scheduler/planner.h"

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

TEST(QuotedText, APlanErrorQuotesThePipelineItWasSent) {
  ShotSpec spec;
  spec.set_pipeline("evil\n[00:00:00] info shot 1 done" + std::string(200, '!'));
  spec.set_frame_end(0);
  try {
    planShot(spec);
    FAIL() << "an unknown pipeline was planned";
  } catch (const PlanError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("\"evil\\x0a[00:00:00] info shot 1 done"), std::string::npos) << message;
    EXPECT_NE(message.find("more bytes)"), std::string::npos) << message;
    EXPECT_LT(message.size(), 300u);
  }
}

}  // namespace
}  // namespace pathfarm::farm

// RoundTrip: replies are matched to requests by sequence number.
#include <gtest/gtest.h>

#include "core/rt/round_trip.h"

namespace {

using enact::rt::RoundTrip;

TEST(RoundTrip, ALateReplyIsNeverTheAnswerToALaterTick) {
  RoundTrip t;
  t.sent(1, 1000);
  t.close();  // tick 1 gave up
  t.sent(2, 2000);
  // tick 1's reply arrives during tick 2: stale, and tick 2 is still open
  EXPECT_FALSE(t.reply(1, 2100));
  EXPECT_TRUE(t.reply(2, 2500));
  EXPECT_EQ(t.last_rtt_ns(), 500);
  EXPECT_EQ(t.requests(), 2u);
  EXPECT_EQ(t.answered(), 1u);
  EXPECT_EQ(t.stale(), 1u);
  EXPECT_EQ(t.unanswered(), 1u);
  EXPECT_EQ(t.rtt().max(), 500);
}

TEST(RoundTrip, ADuplicateOrUnaskedReplyIsStale) {
  RoundTrip t;
  EXPECT_FALSE(t.reply(7, 10));  // nothing asked yet
  t.sent(8, 100);
  EXPECT_TRUE(t.reply(8, 150));
  EXPECT_FALSE(t.reply(8, 160));  // answered already
  EXPECT_EQ(t.stale(), 2u);
  EXPECT_EQ(t.answered(), 1u);
  EXPECT_EQ(t.unanswered(), 0u);
}

TEST(RoundTrip, SendingAgainClosesAnOpenRequestAsUnanswered) {
  RoundTrip t;
  t.sent(1, 0);
  t.sent(2, 200);
  EXPECT_FALSE(t.reply(1, 250));
  EXPECT_EQ(t.unanswered(), 1u);
  EXPECT_EQ(t.answered(), 0u);
}

}  // namespace

// The recordings' and `enact topic`'s loss count per publisher: jumps, and restarts whose
// first messages were missed.
#include <gtest/gtest.h>

#include "core/graph/logger.h"

namespace enact::graph {
namespace {

TEST(SequenceCheck, CountsJumpsAndTheMissedStartOfARestartedStream) {
  SequenceCheck c;
  for (const std::uint64_t seq : {1, 2, 5, 6, 3, 4, 1, 2}) c.add(seq);
  // 3-4 missing; a restart seen at 3 (its 1-2 missing); a restart seen at 1 (nothing missing)
  EXPECT_EQ(c.messages, 8u);
  EXPECT_EQ(c.gaps, 4u);
  EXPECT_EQ(c.restarts, 2u);
}

TEST(SequenceCheck, ALateJoinerLosesNothing) {
  SequenceCheck c;
  for (const std::uint64_t seq : {500, 501, 502}) c.add(seq);
  EXPECT_EQ(c.gaps, 0u);
  EXPECT_EQ(c.restarts, 0u);
}

}  // namespace
}  // namespace enact::graph

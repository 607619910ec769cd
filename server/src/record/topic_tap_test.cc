#include "hadal/record/topic_tap.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace hadal::record {
namespace {

// The recorder's loss accounting (topic_tap.h): only numbers skipped after the first read are lost.
TEST(SequenceGapsTest, OnlyNumbersSkippedAfterTheFirstAreLost) {
  SequenceGaps gaps;
  for (std::int64_t sequence : {4, 5, 6, 9, 10, 14}) gaps.add(sequence);
  EXPECT_EQ(gaps.samples, 6u);
  EXPECT_EQ(gaps.first, 4);  // 1..3 written before the reader matched: not lost
  EXPECT_EQ(gaps.last, 14);
  EXPECT_EQ(gaps.lost, 2u + 3u);  // 7, 8 and 11, 12, 13
  SequenceGaps whole;
  for (std::int64_t sequence = 1; sequence <= 100; ++sequence) whole.add(sequence);
  EXPECT_EQ(whole.lost, 0u);
}

}  // namespace
}  // namespace hadal::record

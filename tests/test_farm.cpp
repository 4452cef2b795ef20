// Farm chunking: a frame list cut into array-job tasks, and each chunk as a --frames text.
#include "base/error.h"
#include "io/sequence.h"

#include <gtest/gtest.h>

#include <random>

using namespace obscura;

TEST(FarmChunks, ConsecutiveChunksCoverEveryFrameOnce) {
    const std::vector<int> frames = parseFrames("1001-1100");
    const auto chunks = chunkFrames(frames, 30);
    ASSERT_EQ(chunks.size(), 4u);  // 30 + 30 + 30 + 10
    EXPECT_EQ(chunks.back().size(), 10u);
    std::vector<int> joined;
    for (const auto& c : chunks) joined.insert(joined.end(), c.begin(), c.end());
    EXPECT_EQ(joined, frames);
    EXPECT_EQ(chunkFrames(frames, 30), chunks);  // deterministic: a resubmission splits the same way
    EXPECT_EQ(chunkFrames(frames, 1000).size(), 1u);
    EXPECT_TRUE(chunkFrames({}, 3).empty());
    EXPECT_THROW(chunkFrames(frames, 0), Error);
}

TEST(FarmChunks, FrameSpecIsShortAndReadsBack) {
    EXPECT_EQ(frameSpec({1, 2, 3, 4}), "1-4");
    EXPECT_EQ(frameSpec({1, 3, 5, 7, 8}), "1-7x2,8");
    EXPECT_EQ(frameSpec({7}), "7");
    EXPECT_EQ(frameSpec({4, 5}), "4-5");
    EXPECT_EQ(frameSpec({4, 6}), "4,6");
    EXPECT_EQ(frameSpec({-3, -2, -1, 0}), "-3-0");
    // Any increasing list, cut anywhere, reads back as the same frames.
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<int> frames;
        int f = (int)(rng() % 40) - 20;
        for (int n = 1 + (int)(rng() % 30); n > 0; --n) frames.push_back(f += 1 + (int)(rng() % 4 == 0 ? rng() % 5 : 0));
        for (const auto& chunk : chunkFrames(frames, 1 + (int)(rng() % 7)))
            EXPECT_EQ(parseFrames(frameSpec(chunk)), chunk) << frameSpec(chunk);
    }
}

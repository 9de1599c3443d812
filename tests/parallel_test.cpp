// Parallel encoding (issue 10): the ordered parallel loop GOMs are coded with, and encodeSequence
// with Threads = 1, 2, 4 giving the same stream, the same callbacks in the same order and the
// same errors; frames read on demand (FrameSource) give what frames read up front give.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "common/core/ordered_parallel.h"
#include "encoder/sequence_encoder.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

TEST(OrderedParallelFor, ConsumesEveryResultInOrder) {
  for (int threads : {1, 2, 4}) {
    std::vector<size_t> seen;
    orderedParallelFor<size_t>(
        50, threads, 3, [](size_t i) { return i * i; },
        [&](size_t i, size_t& square) {
          EXPECT_EQ(square, i * i);
          seen.push_back(i);
        });
    ASSERT_EQ(seen.size(), 50u) << threads;
    for (size_t i = 0; i < seen.size(); ++i)
      EXPECT_EQ(seen[i], i);
  }
}

// No more than `window` items are started ahead of the consumer, whatever the thread count
// (counting the one being consumed: `consumed` here counts finished consume calls).
TEST(OrderedParallelFor, KeepsAtMostWindowItemsInFlight) {
  std::atomic<size_t> consumed{0}, worstAhead{0};
  std::mutex mutex;
  orderedParallelFor<int>(
      40, 4, 3,
      [&](size_t i) {
        std::lock_guard<std::mutex> lock(mutex);
        const size_t ahead = i + 1 - consumed.load();
        if (ahead > worstAhead) worstAhead = ahead;
        return 0;
      },
      [&](size_t i, int&) { consumed = i + 1; });
  EXPECT_EQ(consumed.load(), 40u);
  EXPECT_LE(worstAhead.load(), 3u + 1u);
}

// A failing item is reported when its turn comes: the items before it are consumed, none after.
TEST(OrderedParallelFor, RethrowsTheFirstFailureInOrder) {
  for (int threads : {1, 2, 4}) {
    std::vector<size_t> seen;
    try {
      orderedParallelFor<size_t>(
          30, threads, 8,
          [](size_t i) -> size_t {
            if (i == 7 || i == 9 || i == 20) throw Error("item " + std::to_string(i));
            return i;
          },
          [&](size_t i, size_t&) { seen.push_back(i); });
      ADD_FAILURE() << "no exception with " << threads << " threads";
    } catch (const Error& e) {
      EXPECT_STREQ(e.what(), "item 7");
    }
    EXPECT_EQ(seen.size(), 7u) << threads;
  }
}

TEST(OrderedParallelFor, StopsWhenTheConsumerThrows) {
  std::atomic<size_t> started{0};
  EXPECT_THROW(orderedParallelFor<int>(
                   1000, 4, 4,
                   [&](size_t) {
                     ++started;
                     return 0;
                   },
                   [](size_t i, int&) {
                     if (i == 2) throw std::runtime_error("consumer");
                   }),
               std::runtime_error);
  EXPECT_LE(started.load(), 3u + 4u);  // item 2's window, plus items already running
}

struct Encoded {
  std::vector<uint8_t> stream;
  std::vector<std::string> lines;  // MD5 lines in callback order
  double sumSquaredError = 0;
  int64_t maxAbsError = 0;
};

Encoded encodeWith(const std::vector<Mesh>& frames, EncoderParams params, int threads,
                   bool onDemand) {
  params.threads = threads;
  Encoded e;
  auto onFrame = [&](int frame, const IntMesh& mesh) {
    EXPECT_EQ(frame, static_cast<int>(e.lines.size()));
    e.lines.push_back(geometryHashLine(frame, mesh));
  };
  EncodedSequence coded;
  if (onDemand) {
    FrameSource source;
    source.count = frames.size();
    source.read = [&frames](size_t k) { return frames[k]; };
    const Grid grid = gridForSequence(source, params.gridBits, params.gridFit, threads);
    EXPECT_EQ(grid.origin, gridForSequence(frames, params.gridBits).origin);
    EXPECT_EQ(grid.step, gridForSequence(frames, params.gridBits).step);
    coded = encodeSequence(params, grid, source, onFrame);
    EXPECT_TRUE(coded.frameInputIndex.empty());  // not kept unless asked for
  } else {
    coded = encodeSequence(params, gridForSequence(frames, params.gridBits), frames, {}, onFrame);
    EXPECT_EQ(coded.frameInputIndex.size(), frames.size());
  }
  e.stream = coded.stream;
  e.sumSquaredError = coded.sumSquaredError;
  e.maxAbsError = coded.maxAbsError;
  return e;
}

EncoderParams params(PMeshMode mode, int gomSize, int quantStep, int keyframes) {
  EncoderParams p;
  p.gridBits = 11;
  p.gomSize = gomSize;
  p.pmeshMode = mode;
  p.motionQuantStep = quantStep;
  p.keyframeCount = keyframes;
  return p;
}

// Seven GOMs of 3 frames (the last one of 2) in every coding mode: the stream, the MD5 lines in
// order and the error statistics are the same for 1, 2 and 4 threads and for frames read on
// demand.
TEST(ParallelEncoding, StreamsAreIdenticalForAnyThreadCount) {
  const std::vector<Mesh> frames = test::wobblingSphere(2, 20);
  const EncoderParams cases[] = {
      params(PMeshMode::kD3dmc, 3, 1, 0), params(PMeshMode::kD3dmc, 3, 6, 2),
      params(PMeshMode::kAfxic, 3, 2, 0), params(PMeshMode::kIntra, 3, 1, 0)};
  for (const EncoderParams& p : cases) {
    SCOPED_TRACE("mode " + std::to_string(static_cast<int>(p.pmeshMode)) + ", step " +
                 std::to_string(p.motionQuantStep));
    const Encoded one = encodeWith(frames, p, 1, false);
    ASSERT_EQ(one.lines.size(), frames.size());
    for (int threads : {1, 2, 4})
      for (bool onDemand : {false, true}) {
        SCOPED_TRACE(std::to_string(threads) + " threads" + (onDemand ? ", on demand" : ""));
        const Encoded other = encodeWith(frames, p, threads, onDemand);
        EXPECT_TRUE(other.stream == one.stream);
        EXPECT_EQ(other.lines, one.lines);
        EXPECT_EQ(other.sumSquaredError, one.sumSquaredError);
        EXPECT_EQ(other.maxAbsError, one.maxAbsError);
      }
  }
}

// An unreadable frame and an uncodable GOM are reported as a sequential run reports them: the
// first in frame order, after every frame before it has been handed out.
TEST(ParallelEncoding, ErrorsComeInFrameOrder) {
  std::vector<Mesh> frames = test::wobblingSphere(1, 12);
  frames[8].triangles.pop_back();  // GOM 2 (frames 6..8) changes connectivity
  for (int threads : {1, 2, 4}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    FrameSource source;
    source.count = frames.size();
    source.read = [&frames](size_t k) {
      if (k == 10) throw Error("frame 10 unreadable");
      return frames[k];
    };
    source.name = [](size_t k) { return "f" + std::to_string(k); };
    EncoderParams p = params(PMeshMode::kD3dmc, 3, 1, 0);
    p.threads = threads;
    int handedOut = 0;
    try {
      encodeSequence(p, gridForSequence(frames, p.gridBits), source,
                     [&](int, const IntMesh&) { ++handedOut; });
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("f8: connectivity differs"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(handedOut, 6);
    try {
      gridForSequence(source, p.gridBits, p.gridFit, threads);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_STREQ(e.what(), "frame 10 unreadable");
    }
  }
}

}  // namespace
}  // namespace tdvo

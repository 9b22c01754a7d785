#include "cambio/hal/triple_buffer.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include "cambio/hal/image.hpp"

namespace cambio::hal {
namespace {

TEST(TripleBuffer, ReaderSeesNothingNewUntilPublish) {
  TripleBuffer<int> buffer(0);
  EXPECT_FALSE(buffer.acquire());
  buffer.back() = 5;
  buffer.publish();
  ASSERT_TRUE(buffer.acquire());
  EXPECT_EQ(buffer.front(), 5);
  EXPECT_FALSE(buffer.acquire());
  EXPECT_EQ(buffer.front(), 5);
}

TEST(TripleBuffer, ReaderGetsTheNewestOfSeveralPublishes) {
  TripleBuffer<int> buffer(0);
  for (int v = 1; v <= 4; ++v) {
    buffer.back() = v;
    buffer.publish();
  }
  ASSERT_TRUE(buffer.acquire());
  EXPECT_EQ(buffer.front(), 4);
  EXPECT_EQ(buffer.published_count(), 4u);
}

// Each image is filled with one value (its frame number, mod 256) and stamped with the frame
// number: a reader that sees mixed pixels, or a stamp that disagrees with them, saw a torn frame.
// Every 64 frames the writer waits until the reader has taken one more frame, so the two really
// overlap however the threads are scheduled; between those points the writer runs flat out.
TEST(TripleBuffer, ConcurrentImagesAreNeverTornAndNeverGoBackwards) {
  TripleBuffer<Image> buffer(Image(64, 48, PixelFormat::kGrey8));
  constexpr std::uint64_t kFrames = 64'000;
  constexpr std::uint64_t kPace = 64;
  std::atomic<bool> done{false};
  std::atomic<std::uint64_t> seen{0};
  std::uint64_t torn = 0;
  std::uint64_t backwards = 0;

  std::thread reader([&] {
    std::uint64_t last = 0;
    while (!done.load(std::memory_order_acquire)) {
      if (!buffer.acquire()) continue;
      const Image& image = buffer.front();
      const auto expected = static_cast<std::uint8_t>(image.sequence & 0xff);
      for (const auto pixel : image.pixels) {
        if (pixel != expected) {
          ++torn;
          break;
        }
      }
      if (image.sequence < last) ++backwards;
      last = image.sequence;
      seen.fetch_add(1, std::memory_order_release);
    }
  });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  bool reader_starved = false;
  for (std::uint64_t n = 1; n <= kFrames; ++n) {
    Image& slot = buffer.back();
    slot.sequence = n;
    std::fill(slot.pixels.begin(), slot.pixels.end(), static_cast<std::uint8_t>(n & 0xff));
    buffer.publish();
    if (n % kPace == 0) {
      while (seen.load(std::memory_order_acquire) < n / kPace && !reader_starved) {
        std::this_thread::yield();
        reader_starved = std::chrono::steady_clock::now() > give_up;
      }
    }
  }
  done.store(true, std::memory_order_release);
  reader.join();

  EXPECT_FALSE(reader_starved) << "the reader took no frame for 10 s";
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_GE(seen.load(), kFrames / kPace);
  buffer.acquire();
  EXPECT_EQ(buffer.front().sequence, kFrames);
}

}  // namespace
}  // namespace cambio::hal

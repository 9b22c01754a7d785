#include "cambio/hal/seqlock_channel.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

namespace cambio::hal {
namespace {

// Every field holds the same counter: a reader that ever sees two different values in one read
// has seen a torn write.
struct Sample {
  std::array<std::uint64_t, 13> fields;
  double as_double;
};

Sample make_sample(std::uint64_t n) {
  Sample s{};
  s.fields.fill(n);
  s.as_double = static_cast<double>(n);
  return s;
}

TEST(SeqlockChannel, ReadsBackTheLastWrite) {
  SeqlockChannel<Sample> channel;
  EXPECT_EQ(channel.version(), 0u);
  channel.write(make_sample(7));
  Sample out{};
  EXPECT_EQ(channel.read(out), 1u);
  EXPECT_EQ(out.fields[12], 7u);
  EXPECT_EQ(out.as_double, 7.0);
}

TEST(SeqlockChannel, ConcurrentReaderNeverSeesATornValue) {
  SeqlockChannel<Sample> channel(make_sample(0));
  constexpr std::uint64_t kWrites = 300'000;
  std::atomic<bool> done{false};
  std::atomic<std::uint64_t> torn{0};
  std::atomic<std::uint64_t> reads{0};
  std::atomic<std::uint64_t> went_backwards{0};

  std::thread reader([&] {
    std::uint64_t last = 0;
    Sample out{};
    while (!done.load(std::memory_order_acquire)) {
      channel.read(out);
      for (const auto field : out.fields) {
        if (field != out.fields[0]) ++torn;
      }
      if (out.as_double != static_cast<double>(out.fields[0])) ++torn;
      if (out.fields[0] < last) ++went_backwards;
      last = out.fields[0];
      ++reads;
    }
  });
  for (std::uint64_t n = 1; n <= kWrites; ++n) channel.write(make_sample(n));
  done.store(true, std::memory_order_release);
  reader.join();

  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(went_backwards.load(), 0u);
  EXPECT_GT(reads.load(), 0u);
  Sample final_value{};
  channel.read(final_value);
  EXPECT_EQ(final_value.fields[0], kWrites);
}

}  // namespace
}  // namespace cambio::hal

// Cost of the latest-value channels and the joint loop's cycle, beside a plain copy of the same
// bytes (the floor any channel pays).
#include <benchmark/benchmark.h>

#include <cstring>

#include "cambio/control/joint_frames.hpp"
#include "cambio/hal/image.hpp"
#include "cambio/hal/seqlock_channel.hpp"
#include "cambio/hal/triple_buffer.hpp"

namespace cambio {
namespace {

void BM_PlainCopyJointTargetFrame(benchmark::State& state) {
  control::JointTargetFrame source;
  control::JointTargetFrame destination;
  for (auto _ : state) {
    std::memcpy(static_cast<void*>(&destination), &source, sizeof source);
    benchmark::DoNotOptimize(destination);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_PlainCopyJointTargetFrame);

void BM_SeqlockWriteReadJointTargetFrame(benchmark::State& state) {
  hal::SeqlockChannel<control::JointTargetFrame> channel;
  control::JointTargetFrame frame;
  for (auto _ : state) {
    frame.stamp_ns++;
    channel.write(frame);
    channel.read(frame);
    benchmark::DoNotOptimize(frame);
  }
}
BENCHMARK(BM_SeqlockWriteReadJointTargetFrame);

void BM_TripleBufferPublishAcquireImage(benchmark::State& state) {
  hal::TripleBuffer<hal::Image> buffer(hal::Image(640, 480, hal::PixelFormat::kRgb8));
  for (auto _ : state) {
    buffer.back().sequence++;
    buffer.publish();
    benchmark::DoNotOptimize(buffer.acquire());
    benchmark::DoNotOptimize(buffer.front().sequence);
  }
}
BENCHMARK(BM_TripleBufferPublishAcquireImage);

}  // namespace
}  // namespace cambio

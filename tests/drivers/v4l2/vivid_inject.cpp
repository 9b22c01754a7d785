// vivid_inject: a stereo pair's source for the guest tests, through vivid's looped HDMI instances.
//   vivid_inject --write-pair DIR SHIFT_PX   writes DIR/left.pgm and DIR/right.pgm (640x480): a
//       band-limited texture, the right image the left moved SHIFT_PX to the left (x_left -
//       x_right = SHIFT_PX at every pixel), what `cambio perceive` reads;
//   vivid_inject OUTPUT CAPTURE IMAGE.pgm    streams the grey image as YUYV (limited range, the
//       chroma neutral) to an instance's output until SIGINT or SIGTERM, so its capture node
//       returns it to whoever streams from it (cambio run's v4l2 cameras).
#include <signal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "vivid_injector.hpp"

namespace {

using cambio::v4l2::vivid::kHeight;
using cambio::v4l2::vivid::kWidth;

double texture(double u, double v) {
  // Eight plane waves of periods 9-40 px, fixed: every run injects the same pair.
  static const std::vector<std::array<double, 3>> waves = [] {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> period(9.0, 40.0);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    std::vector<std::array<double, 3>> w(8);
    for (auto& wave : w) {
      const double p = period(rng);
      const double a = angle(rng);
      wave = {2.0 * M_PI * std::cos(a) / p, 2.0 * M_PI * std::sin(a) / p, angle(rng)};
    }
    return w;
  }();
  double value = 0.0;
  for (const auto& w : waves) value += std::sin(w[0] * u + w[1] * v + w[2]);
  return 128.0 + 100.0 * value / static_cast<double>(waves.size());
}

bool write_pgm(const std::string& path, double shift_px) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << kWidth << " " << kHeight << "\n255\n";
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      out.put(static_cast<char>(std::clamp(std::lround(texture(x + shift_px, y)), 0L, 255L)));
    }
  }
  return static_cast<bool>(out);
}

std::vector<std::uint8_t> read_pgm_as_yuyv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int width = 0;
  int height = 0;
  int maxval = 0;
  in >> magic >> width >> height >> maxval;
  in.get();
  if (magic != "P5" || width != kWidth || height != kHeight || maxval != 255) {
    throw std::runtime_error(path + ": expected a 640x480 8-bit binary PGM");
  }
  std::vector<std::uint8_t> grey(static_cast<std::size_t>(kWidth) * kHeight);
  in.read(reinterpret_cast<char*>(grey.data()), static_cast<std::streamsize>(grey.size()));
  if (!in) throw std::runtime_error(path + ": cut short");
  std::vector<std::uint8_t> yuyv(grey.size() * 2);
  for (std::size_t i = 0; i < grey.size(); ++i) {
    yuyv[2 * i] = static_cast<std::uint8_t>(std::lround(16.0 + grey[i] * 219.0 / 255.0));
    yuyv[2 * i + 1] = 128;
  }
  return yuyv;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 4 && std::string(argv[1]) == "--write-pair") {
      const std::string dir = argv[2];
      const double shift_px = std::stod(argv[3]);
      if (!write_pgm(dir + "/left.pgm", 0.0) || !write_pgm(dir + "/right.pgm", shift_px)) {
        std::cerr << "vivid_inject: cannot write the pair in " << dir << "\n";
        return 1;
      }
      return 0;
    }
    if (argc != 4) {
      std::cerr << "usage: vivid_inject OUTPUT CAPTURE IMAGE.pgm | --write-pair DIR SHIFT_PX\n";
      return 2;
    }
    sigset_t stop;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop, nullptr);  // Before the pump's thread: it inherits it.
    cambio::v4l2::vivid::Injector injector(argv[1], argv[2], read_pgm_as_yuyv(argv[3]));
    injector.start();
    std::cout << "vivid_inject: " << argv[3] << " -> " << argv[1] << " -> " << argv[2] << std::endl;
    int signal_number = 0;
    sigwait(&stop, &signal_number);
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "vivid_inject: " << error.what() << "\n";
    return 1;
  }
}

// Planar float images for the denoiser (one plane per channel, row-major), and the meter that
// counts the bytes they hold: the denoiser's peak is measured, and a test holds denoise_bytes()
// (denoise.h) to it.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

namespace anamorph::nfor {

// Bytes held now and at most, over every Planes and scratch buffer that reports to it. Atomic:
// scratch buffers come and go on several threads at once.
class MemoryMeter {
 public:
  void add(size_t bytes) {
    const size_t now = live_.fetch_add(bytes) + bytes;
    size_t peak = peak_.load();
    while (now > peak && !peak_.compare_exchange_weak(peak, now)) {
    }
  }
  void remove(size_t bytes) { live_.fetch_sub(bytes); }
  size_t peak() const { return peak_.load(); }
  size_t live() const { return live_.load(); }

 private:
  std::atomic<size_t> live_{0}, peak_{0};
};

// A float buffer whose size the meter counts for as long as it lives (nullptr: not counted).
class MeteredFloats {
 public:
  MeteredFloats() = default;
  MeteredFloats(size_t n, MemoryMeter* meter) : v_(n, 0.0f), meter_(meter) {
    if (meter_) meter_->add(bytes());
  }
  MeteredFloats(MeteredFloats&& o) noexcept : v_(std::move(o.v_)), meter_(o.meter_) {
    o.v_ = {};
    o.meter_ = nullptr;
  }
  MeteredFloats& operator=(MeteredFloats&& o) noexcept {
    if (this != &o) {
      release();
      v_ = std::move(o.v_);
      meter_ = o.meter_;
      o.v_ = {};
      o.meter_ = nullptr;
    }
    return *this;
  }
  MeteredFloats(const MeteredFloats&) = delete;
  MeteredFloats& operator=(const MeteredFloats&) = delete;
  ~MeteredFloats() { release(); }

  float* data() { return v_.data(); }
  const float* data() const { return v_.data(); }
  size_t size() const { return v_.size(); }
  float& operator[](size_t i) { return v_[i]; }
  float operator[](size_t i) const { return v_[i]; }
  // Frees the storage now (the meter sees it go).
  void release() {
    if (meter_) meter_->remove(bytes());
    meter_ = nullptr;
    v_ = {};
  }

 private:
  size_t bytes() const { return v_.size() * sizeof(float); }
  std::vector<float> v_;
  MemoryMeter* meter_ = nullptr;
};

// `channels` planes of width × height floats, zeroed.
class Planes {
 public:
  Planes() = default;
  Planes(int width, int height, int channels, MemoryMeter* meter)
      : w_(width), h_(height), c_(channels), v_(size_t(width) * height * channels, meter) {}
  int width() const { return w_; }
  int height() const { return h_; }
  int channels() const { return c_; }
  size_t pixels() const { return size_t(w_) * size_t(h_); }
  float* plane(int c) { return v_.data() + size_t(c) * pixels(); }
  const float* plane(int c) const { return v_.data() + size_t(c) * pixels(); }
  float& at(int c, int x, int y) { return plane(c)[size_t(y) * w_ + x]; }
  float at(int c, int x, int y) const { return plane(c)[size_t(y) * w_ + x]; }
  bool empty() const { return v_.size() == 0; }
  void release() {
    v_.release();
    w_ = h_ = c_ = 0;
  }

 private:
  int w_ = 0, h_ = 0, c_ = 0;
  MeteredFloats v_;
};

}  // namespace anamorph::nfor

// Images written strip by strip from the top, so a frame never has to be in memory at once
// (`anamorph render` streams finished tiles through these). Both write into an AtomicFile: the
// file appears under its name only on commit(), complete; commit_as() puts the image somewhere
// else (an interrupted render's "image so far"). The whole-image writers (write_png, write_exr)
// are these with every row at once.
#pragma once

#include <zlib.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "io/image_sink.h"

namespace anamorph {

// PNG, RGBA8. A band of rows is filtered and deflated on its own (its first row without the
// row above, its deflate stream ending on a full flush), so bands are encoded on any thread,
// in any order, and appended in order: the bytes depend on the band boundaries only.
class PngStream {
 public:
  struct Band {
    std::string deflated;
    uLong adler = 0;
    size_t raw_bytes = 0;
  };
  PngStream(const std::filesystem::path& file, int width, int height,
            const std::map<std::string, std::string>& metadata);
  ~PngStream();
  int width() const { return width_; }
  int height() const { return height_; }
  // `rows` rows of `width` RGBA8 pixels. Thread-safe (no state).
  static Band encode(const unsigned char* rgba, int width, int rows);
  // The next band from the top; `rows` of them. Not thread-safe: one caller at a time.
  void append(const Band& band, int rows);
  void commit();
  void commit_as(const std::filesystem::path& other);
  int rows_written() const { return rows_; }

 private:
  void finish();
  std::filesystem::path file_;
  std::unique_ptr<AtomicFile> out_;
  int width_, height_, rows_ = 0;
  uLong adler_;
};

// EXR through OpenEXR: 32-bit float channels named "<layer>.<c>" (bare "<c>" for the unnamed
// beauty layer), ZIP-compressed scanlines in increasing y, metadata as string attributes.
class ExrStream {
 public:
  ExrStream(const std::filesystem::path& file, int width, int height,
            const std::vector<LayerSpec>& layers,
            const std::map<std::string, std::string>& metadata);
  ~ExrStream();
  // Rows [rows_written(), + rows) of every layer, each interleaved as ImageLayer::data (rows x
  // width x channels), in the order of `layers`. One caller at a time.
  void write_rows(const std::vector<const float*>& layers, int rows);
  void commit();
  void commit_as(const std::filesystem::path& other);
  int rows_written() const { return rows_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int rows_ = 0;
};

}  // namespace anamorph

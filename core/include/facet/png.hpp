// PNG output that needs no whole image in memory, and can be compressed in
// parallel: an 8-bit RGBA image is written as segments of kPngSegmentRows
// rows, each filtered and deflated on its own (as pigz does), so that
// threads or machines can encode their rows where they render them and one
// writer only joins the bytes. The segments form one zlib stream; every
// decoder reads the file as any other PNG.
//
// Whoever encodes a segment (write_png, a render thread, an MPI rank), the
// file's bytes depend only on the pixels: a band-split render writes the
// same file as a whole one.
#pragma once

#include <cstddef>
#include <cstdint>
#include "facet/output.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace facet {

constexpr int kPngSegmentRows = 64;

class OutputFile;  // core/src/base/output_file.hpp


// One segment's rows, filtered and deflated: raw deflate that ends on a
// byte boundary (the image's last segment ends the stream).
struct PngSegment {
    std::string deflated;
    int rows = 0;
    uint32_t adler = 1;      // Adler-32 of its filtered bytes
    uint64_t raw_bytes = 0;  // how many filtered bytes it holds
};

// Encodes `rows` rows of `width` RGBA pixels (row y at rgba + y * stride
// bytes) as one segment; `ends_image` when they are the image's last.
PngSegment encode_png_segment(const uint8_t* rgba, size_t stride, int width, int rows,
                              bool ends_image);

// Writes a PNG from its segments in order, to `path`: "-" is standard
// output, and a device or FIFO is written where it is. A file is written
// beside it under a name of its own ("<path>.<pid>-<n>.part") and renamed
// into place by finish(), so a writer that stops early (an error, a signal,
// a crash) never leaves a truncated image where the image should be, and
// two writers never mix their bytes (core/src/base/output_file.hpp). Throws
// Error(output_failed) naming the file and the cause.
class PngWriter {
public:
    PngWriter(const std::filesystem::path& path, int width, int height);
    ~PngWriter();  // unfinished: removes the partial file
    PngWriter(const PngWriter&) = delete;
    PngWriter& operator=(const PngWriter&) = delete;

    // The next segment: rows [rows_written(), + segment.rows).
    void add(const PngSegment& segment);
    int rows_written() const { return rows_; }
    // After the last row: ends the file and moves it into place.
    void finish();

private:
    void start();  // the signature, the header and the stream's header
    void chunk(const char type[4], const void* data, size_t size);
    void put(const void* data, size_t size);

    std::filesystem::path path_;
    std::unique_ptr<OutputFile> file_;
    int width_, height_, rows_ = 0;
    uint32_t adler_ = 1;
};

// The segments of rows [first_row, first_row + rows) of an image `height`
// rows tall (first_row a multiple of kPngSegmentRows; row first_row at
// rgba), encoded on up to `threads` threads (0: one per hardware thread).
std::vector<PngSegment> encode_png_rows(const uint8_t* rgba, size_t stride, int width,
                                        int first_row, int rows, int height, int threads = 0);

// Encodes rows [0, height) of an image in segments on up to `threads`
// threads (0: one per hardware thread) and writes them to `path`.
void write_png_rows(const std::filesystem::path& path, const uint8_t* rgba, size_t stride,
                    int width, int height, int threads = 0);

}  // namespace facet

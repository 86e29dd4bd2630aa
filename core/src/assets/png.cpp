// PNG output in independently deflated segments (facet/png.hpp).
#include "facet/png.hpp"

#include "facet/error.hpp"
#include "base/output_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <thread>

namespace facet {

namespace {

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// Row `row` filtered with each of PNG's five filters, the one whose bytes
// (as signed) sum smallest in magnitude first (the heuristic the PNG
// specification suggests). `above` is null in a segment's first row: then
// only the filters that do not read the row above (None, Sub) are tried,
// so that a segment decodes the same whatever precedes it.
void filter_row(const uint8_t* row, const uint8_t* above, size_t bytes, uint8_t* out,
                std::vector<uint8_t>& trial) {
    trial.resize(bytes);
    uint64_t best = UINT64_MAX;
    const int filters = above ? 5 : 2;
    for (int f = 0; f < filters; ++f) {
        uint64_t cost = 0;
        for (size_t i = 0; i < bytes; ++i) {
            const int a = i >= 4 ? row[i - 4] : 0, b = above ? above[i] : 0;
            const int c = above && i >= 4 ? above[i - 4] : 0;
            int predicted = 0;
            switch (f) {
                case 1: predicted = a; break;
                case 2: predicted = b; break;
                case 3: predicted = (a + b) / 2; break;
                case 4: predicted = paeth(a, b, c); break;
                default: break;
            }
            const uint8_t v = uint8_t(row[i] - predicted);
            trial[i] = v;
            cost += uint64_t(v < 128 ? v : 256 - v);
        }
        if (cost < best) {
            best = cost;
            out[0] = uint8_t(f);
            std::memcpy(out + 1, trial.data(), bytes);
        }
    }
}

// A chunk's CRC covers its type and its data. (zlib's crc32 of a null
// buffer is 0, not the CRC so far: an empty chunk's data is left out.)
uint32_t crc(const char type[4], const void* data, size_t size) {
    uLong c = crc32(0L, reinterpret_cast<const Bytef*>(type), 4);
    if (size > 0) c = crc32_z(c, static_cast<const Bytef*>(data), size);
    return uint32_t(c);
}

void put_u32(uint8_t* out, uint32_t v) {
    out[0] = uint8_t(v >> 24);
    out[1] = uint8_t(v >> 16);
    out[2] = uint8_t(v >> 8);
    out[3] = uint8_t(v);
}

}  // namespace

PngSegment encode_png_segment(const uint8_t* rgba, size_t stride, int width, int rows,
                              bool ends_image) {
    const size_t bytes = size_t(width) * 4;
    std::vector<uint8_t> filtered(size_t(rows) * (bytes + 1)), trial;
    for (int y = 0; y < rows; ++y)
        filter_row(rgba + size_t(y) * stride, y > 0 ? rgba + size_t(y - 1) * stride : nullptr,
                   bytes, filtered.data() + size_t(y) * (bytes + 1), trial);
    PngSegment s;
    s.rows = rows;
    s.raw_bytes = filtered.size();
    s.adler = uint32_t(adler32_z(1L, filtered.data(), filtered.size()));
    z_stream z{};
    // Raw deflate (no zlib header): the writer puts the stream's one header
    // first and its Adler-32 last.
    if (deflateInit2(&z, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::bad_alloc();
    s.deflated.resize(deflateBound(&z, uLong(filtered.size())) + 16);
    z.next_in = filtered.data();
    z.avail_in = uInt(filtered.size());
    z.next_out = reinterpret_cast<Bytef*>(s.deflated.data());
    z.avail_out = uInt(s.deflated.size());
    // A sync flush ends on a byte boundary with the stream still open, so
    // the next segment's blocks follow it; the last segment ends the stream.
    const int status = deflate(&z, ends_image ? Z_FINISH : Z_SYNC_FLUSH);
    const size_t produced = s.deflated.size() - z.avail_out;
    deflateEnd(&z);
    if (status != (ends_image ? Z_STREAM_END : Z_OK) || z.avail_in != 0)
        throw Error(ErrorCode::output_failed, "deflate failed while encoding a PNG segment");
    s.deflated.resize(produced);
    return s;
}

PngWriter::PngWriter(const std::filesystem::path& path, int width, int height)
    : path_(path), width_(width), height_(height) {
    if (width < 1 || height < 1)
        throw Error(ErrorCode::output_failed, "a PNG needs at least one pixel", path.string());
    file_ = std::make_unique<OutputFile>(path);
    start();
}

void PngWriter::start() {
    static const uint8_t signature[8] = {137, 'P', 'N', 'G', '\r', '\n', 26, '\n'};
    put(signature, 8);
    uint8_t header[13];
    put_u32(header, uint32_t(width_));
    put_u32(header + 4, uint32_t(height_));
    header[8] = 8;   // bits per channel
    header[9] = 6;   // RGBA
    header[10] = header[11] = header[12] = 0;  // deflate, adaptive filters, no interlace
    chunk("IHDR", header, sizeof header);
    static const uint8_t zlib_header[2] = {0x78, 0x9C};  // deflate, 32 KiB window
    chunk("IDAT", zlib_header, 2);
}

PngWriter::~PngWriter() = default;

void PngWriter::put(const void* data, size_t size) { file_->write(data, size); }

void PngWriter::chunk(const char type[4], const void* data, size_t size) {
    uint8_t head[8], tail[4];
    put_u32(head, uint32_t(size));
    std::memcpy(head + 4, type, 4);
    put_u32(tail, crc(type, data, size));
    put(head, 8);
    if (size > 0) put(data, size);  // IEND has none, and no pointer to it
    put(tail, 4);
}

void PngWriter::add(const PngSegment& segment) {
    const int rows = segment.rows;
    if (rows < 1 || rows > height_ - rows_)
        throw Error(ErrorCode::output_failed,
                    "a PNG segment of " + std::to_string(rows) + " rows after " +
                        std::to_string(rows_) + " of " + std::to_string(height_),
                    path_.string());
    // At most 2^31 - 1 bytes a chunk; a segment is far smaller in practice.
    for (size_t at = 0; at < segment.deflated.size(); at += size_t(1) << 30)
        chunk("IDAT", segment.deflated.data() + at,
              std::min(segment.deflated.size() - at, size_t(1) << 30));
    adler_ = uint32_t(adler32_combine(adler_, segment.adler, z_off_t(segment.raw_bytes)));
    rows_ += rows;
}

void PngWriter::finish() {
    if (rows_ != height_)
        throw Error(ErrorCode::output_failed,
                    "the PNG ends after " + std::to_string(rows_) + " of its " +
                        std::to_string(height_) + " rows",
                    path_.string());
    uint8_t adler[4];
    put_u32(adler, adler_);
    chunk("IDAT", adler, 4);
    chunk("IEND", nullptr, 0);
    file_->commit();
}

std::vector<PngSegment> encode_png_rows(const uint8_t* rgba, size_t stride, int width,
                                        int first_row, int rows, int height, int threads) {
    // Segments start every kPngSegmentRows rows of the image, whoever
    // encodes them: that is what makes the bytes the same however split.
    if (first_row % kPngSegmentRows != 0 || rows < 1 || first_row + rows > height)
        throw Error(ErrorCode::output_failed,
                    "PNG rows " + std::to_string(first_row) + ".." +
                        std::to_string(first_row + rows - 1) + " of " + std::to_string(height) +
                        " do not start a segment of " + std::to_string(kPngSegmentRows) + " rows");
    const int count = (rows + kPngSegmentRows - 1) / kPngSegmentRows;
    std::vector<PngSegment> out(size_t(std::max(count, 0)));
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    threads = std::min(threads, count);
    const auto encode = [&](int i) {
        const int y = i * kPngSegmentRows, n = std::min(kPngSegmentRows, rows - y);
        out[size_t(i)] = encode_png_segment(rgba + size_t(y) * stride, stride, width, n,
                                            first_row + y + n == height);
    };
    // Thread t encodes every threads-th segment from t; the caller is thread 0.
    std::exception_ptr failed;
    std::mutex lock;
    const auto run = [&](int t) {
        try {
            for (int i = t; i < count; i += threads) encode(i);
        } catch (...) {
            const std::lock_guard<std::mutex> hold(lock);
            failed = std::current_exception();
        }
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back(run, t);
    run(0);
    for (std::thread& w : workers) w.join();
    if (failed) std::rethrow_exception(failed);
    return out;
}

void write_png_rows(const std::filesystem::path& path, const uint8_t* rgba, size_t stride,
                    int width, int height, int threads) {
    PngWriter writer(path, width, height);
    // A window of rows at a time: the encoded bytes wait for the file, not
    // the whole image's.
    const int window = kPngSegmentRows * 32;
    for (int y = 0; y < height; y += window) {
        const int rows = std::min(window, height - y);
        const std::vector<PngSegment> segments =
            encode_png_rows(rgba + size_t(y) * stride, stride, width, y, rows, height, threads);
        for (const PngSegment& s : segments) writer.add(s);
    }
    writer.finish();
}

}  // namespace facet

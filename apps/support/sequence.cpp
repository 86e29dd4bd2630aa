// Frame sequences and band-split images (sequence.hpp).
#include "facet/sequence.hpp"

#include <facet/error.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cmath>
#include <cstdio>

namespace facet {

namespace {

// A whole number of at most 12 digits; nullopt otherwise.
std::optional<long> parse_frame_number(const std::string& text) {
    if (text.empty() || text.size() > 12 ||
        !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); }))
        return std::nullopt;
    return std::stol(text);
}

// Where the one conversion of a checked pattern starts and ends.
struct Conversion {
    size_t begin = std::string::npos, end = 0;
    int width = 0;
    bool zeros = false;
};

Conversion find_conversion(const std::string& pattern, std::string& error) {
    Conversion found;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') continue;
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            ++i;
            continue;
        }
        size_t j = i + 1;
        Conversion c;
        c.begin = i;
        if (j < pattern.size() && pattern[j] == '0') c.zeros = true, ++j;
        while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) &&
               c.width < 100)
            c.width = c.width * 10 + (pattern[j++] - '0');
        if (j >= pattern.size() || pattern[j] != 'd' || c.width > 18) {
            error = "'" + pattern + "' has a conversion other than %d, %Nd or %0Nd at " +
                    std::to_string(i + 1);
            return {};
        }
        if (found.begin != std::string::npos) {
            error = "'" + pattern + "' has more than one %d";
            return {};
        }
        c.end = j + 1;
        found = c;
        i = j;
    }
    if (found.begin == std::string::npos && error.empty())
        error = "'" + pattern + "' has no %d for the frame number (e.g. out_%04d.png)";
    return found;
}

}  // namespace

std::optional<FrameRange> parse_frames(const std::string& text, const Timeline& timeline,
                                       std::string& error) {
    if (text == "all") {
        if (!timeline.animated()) {
            error = "the scene does not move (no animation: key, no animate: tracks), so 'all' "
                    "names no frame; give A..B";
            return std::nullopt;
        }
        const FrameRange r{timeline.first_frame(), timeline.end_frame() - 1};
        if (r.last < r.first) {
            error = "the scene's animation is shorter than one frame";
            return std::nullopt;
        }
        return r;
    }
    const size_t dots = text.find("..");
    const auto first = parse_frame_number(dots == std::string::npos ? text : text.substr(0, dots));
    const auto last = dots == std::string::npos ? first : parse_frame_number(text.substr(dots + 2));
    if (!first || !last || *last < *first) {
        error = "expected A..B (frame numbers, A <= B), N or all, got '" + text + "'";
        return std::nullopt;
    }
    return FrameRange{*first, *last};
}

std::pair<FrameRange, double> frames_to_render(const std::string& text, double fps,
                                               Timeline timeline) {
    if (fps > 0.0) timeline.fps = fps;
    std::string error;
    const std::optional<FrameRange> range = parse_frames(text, timeline, error);
    if (!range) throw Error(ErrorCode::config_invalid, error, "--frames");
    return {*range, timeline.fps};
}

std::string check_finite_times(const std::optional<double>& time, double fps) {
    if (time && !std::isfinite(*time)) return "--time: expected a number of seconds, got nan";
    if (!std::isfinite(fps)) return "--fps: expected a number of frames a second, got nan";
    return {};
}

std::string check_frame_pattern(const std::string& pattern) {
    std::string error;
    find_conversion(pattern, error);
    return error;
}

std::string frame_path(const std::string& pattern, long frame) {
    std::string error;
    const Conversion c = find_conversion(pattern, error);
    if (!error.empty()) throw Error(ErrorCode::config_invalid, error);
    std::string number = std::to_string(frame);
    if (int(number.size()) < c.width)
        number.insert(0, size_t(c.width) - number.size(), c.zeros ? '0' : ' ');
    std::string out;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (i == c.begin) {
            out += number;
            i = c.end - 1;
        } else {
            out += pattern[i];
            if (pattern[i] == '%' && i + 1 < pattern.size() && pattern[i + 1] == '%') ++i;
        }
    }
    return out;
}

FrameStats render_frame_to_png(Renderer& renderer, Scene& scene, long frame, double fps,
                               const std::string& path, Framebuffer& target,
                               std::vector<uint8_t>& rgba) {
    scene.pose(double(frame) / fps);
    const FrameStats stats = renderer.render(scene, target);
    renderer.pipeline().resolve_srgb8(target, rgba);
    write_png_rows(path, rgba.data(), size_t(target.width()) * 4, target.width(),
                   target.height(), renderer.threads());
    return stats;
}

int band_rows(int rows) {
    return std::max(1, (rows + kPngSegmentRows - 1) / kPngSegmentRows) * kPngSegmentRows;
}

void check_band(int width, int rows) {
    if (int64_t(width) * rows <= Framebuffer::kMaxPixels) return;
    const int64_t most = Framebuffer::kMaxPixels / width / kPngSegmentRows * kPngSegmentRows;
    throw Error(ErrorCode::out_of_range,
                "a band of " + std::to_string(width) + "x" + std::to_string(rows) +
                    " pixels is more than one target holds; at most " + std::to_string(most) +
                    " rows at this width",
                "--band-rows");
}

int band_count(int height, int rows) { return (height + rows - 1) / rows; }

std::vector<PngSegment> render_band(Renderer& renderer, const Scene& scene, int band, int rows,
                                    Framebuffer& target, std::vector<uint8_t>& rgba) {
    const int height = scene.settings.height, width = scene.settings.width;
    const int first = band * rows, count = std::min(rows, height - first);
    renderer.render_rows(scene, first, count, target);
    renderer.pipeline().resolve_srgb8(target, rgba);
    return encode_png_rows(rgba.data(), size_t(width) * 4, width, first, count, height,
                           renderer.threads());
}

Progress::Progress(std::string what, long total)
    : what_(std::move(what)), total_(total), start_(std::chrono::steady_clock::now()),
      last_(start_) {}

void Progress::skipped() {
    --total_;
    last_ = std::chrono::steady_clock::now();  // the next item starts now
}

void Progress::done(const std::string& label, double seconds) {
    const auto now = std::chrono::steady_clock::now();
    ++done_;
    const double last = seconds >= 0.0 ? seconds : std::chrono::duration<double>(now - last_).count();
    const double all = std::chrono::duration<double>(now - start_).count();
    last_ = now;
    const long left = std::max(0L, total_ - done_);
    spdlog::info("{} {}/{} ({:.0f}%): {} in {}; {} left", what_, done_, total_,
                 total_ > 0 ? 100.0 * double(done_) / double(total_) : 100.0, label,
                 format_duration(last),
                 left == 0 ? std::string("none") : "about " + format_duration(all / double(done_) * double(left)));
}

std::string format_duration(double seconds) {
    char text[48];
    if (!(seconds >= 0.0)) seconds = 0.0;
    if (seconds < 1.0) std::snprintf(text, sizeof text, "%.0f ms", seconds * 1000.0);
    else if (seconds < 60.0) std::snprintf(text, sizeof text, "%.1f s", seconds);
    else if (seconds < 3600.0)
        std::snprintf(text, sizeof text, "%d min %02d s", int(seconds / 60.0),
                      int(std::fmod(seconds, 60.0)));
    else
        std::snprintf(text, sizeof text, "%d h %02d min", int(seconds / 3600.0),
                      int(std::fmod(seconds, 3600.0) / 60.0));
    return text;
}

}  // namespace facet

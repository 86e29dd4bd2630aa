// Frame sequences and band-split images, as facet-render and
// facet-render-mpi make them.
//
// A sequence's frame k shows the scene posed at time k / fps
// (Scene::pose); its file is the output pattern with k in it
// ("out_%04d.png"). A large image is made in bands of rows
// (Renderer::render_rows), each encoded into PNG segments where it was
// rendered (facet/png.hpp), so no process holds the whole image. Either
// way the bytes written depend only on the scene and the frame: not on
// which process rendered what, nor in which order.
#pragma once

#include <facet/png.hpp>
#include <facet/renderer.hpp>
#include <facet/scene.hpp>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace facet {

// Frames first..last, inclusive.
struct FrameRange {
    long first = 0;
    long last = 0;
    long count() const { return last - first + 1; }
};

// "A..B" (A <= B), "N" (one frame) or "all" (the scene's time line:
// Timeline::first_frame() up to, not including, end_frame()). nullopt with
// `error` set when the text is none of these, or "all" names no frame.
std::optional<FrameRange> parse_frames(const std::string& text, const Timeline& timeline,
                                       std::string& error);

// The frames `--frames` names (`text`) at `fps` (0: the time line's), and
// the fps: "all" counts the frames at that fps. Throws
// Error(config_invalid) naming --frames when the text is bad.
std::pair<FrameRange, double> frames_to_render(const std::string& text, double fps,
                                               Timeline timeline);

// Why --time or --fps is not a finite number (CLI11's range checks let NaN
// through), or "".
std::string check_finite_times(const std::optional<double>& time, double fps);

// Checks that `pattern` holds exactly one integer conversion (%d, or
// with a width and zero padding: %4d, %04d) and no other, "%%" aside.
// Returns why not, or "".
std::string check_frame_pattern(const std::string& pattern);
// The pattern with `frame` in place of its conversion.
std::string frame_path(const std::string& pattern, long frame);

// Renders frame `frame` of `scene` at `fps` into `target` (its 8-bit
// pixels into `rgba`) and writes it to `path`. The scene is posed first, so
// the image is the same whatever was rendered before. Returns the frame's
// statistics.
FrameStats render_frame_to_png(Renderer& renderer, Scene& scene, long frame, double fps,
                               const std::string& path, Framebuffer& target,
                               std::vector<uint8_t>& rgba);

// Rows per band when none are asked for: 256 rows of a 32768-wide image
// take 32 MiB in 8-bit RGBA.
constexpr int kDefaultBandRows = 256;

// Rows per band: `rows` rounded up to whole PNG segments.
int band_rows(int rows);
// Throws Error(out_of_range) naming --band-rows when a
// band of `rows` rows of a `width`-wide image is more than one target holds
// (Framebuffer::kMaxPixels).
void check_band(int width, int rows);
// The bands of an image `height` rows tall, `rows` each (the last may be
// shorter): band b is rows [b * rows, min(height, (b + 1) * rows)).
int band_count(int height, int rows);

// Band `band` of `scene`'s image (bands of `rows` rows), rendered and
// encoded as the PNG segments of its rows.
std::vector<PngSegment> render_band(Renderer& renderer, const Scene& scene, int band, int rows,
                                    Framebuffer& target, std::vector<uint8_t>& rgba);

// Progress with an estimate of the time left: after each item, how many
// are done, how long it took, and the time left at the pace so far.
class Progress {
public:
    Progress(std::string what, long total);
    // Logs one line for an item done (`label`, e.g. "frame 12") that took
    // `seconds` (< 0: the time since the item before).
    void done(const std::string& label, double seconds = -1.0);
    void skipped();
    long finished() const { return done_; }

private:
    std::string what_;
    long total_, done_ = 0;
    std::chrono::steady_clock::time_point start_, last_;
};

// "1 h 02 min", "3 min 05 s", "4.2 s".
std::string format_duration(double seconds);

}  // namespace facet

// The bitmap font and overlay drawing: properties of the glyph table, exact
// pixels against a per-pixel reference, measurement, clipping (checked with
// guard bytes around the image), the hollow box and alpha blending.
#include <facet/text.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

using namespace facet;

namespace {

constexpr Rgba8 kWhite{255, 255, 255, 255};

// A glyph as text, '#' and '.', row by row: a key for comparing glyphs.
std::string glyph_art(char c) {
    std::string art;
    for (int row = 0; row < kGlyphHeight; ++row)
        for (int col = 0; col < kGlyphWidth; ++col) art += glyph_pixel(c, col, row) ? '#' : '.';
    return art;
}

int lit_in_rows(char c, int row0, int row1) {
    int n = 0;
    for (int row = row0; row <= row1; ++row)
        for (int col = 0; col < kGlyphWidth; ++col) n += glyph_pixel(c, col, row);
    return n;
}

int lit_count(char c) { return lit_in_rows(c, 0, kGlyphHeight - 1); }

// The reference: whether draw_text(x0, y0, text, scale) covers pixel (x, y),
// worked out per pixel from the glyph table and the documented metrics.
bool reference_lit(const std::string& text, long long x0, long long y0, int scale, long long x,
                   long long y) {
    const long long dx = x - x0, dy = y - y0;
    if (dx < 0 || dy < 0) return false;
    const long long font_x = dx / scale, font_y = dy / scale;
    long long line = font_y / kLineHeight, start = 0;
    for (; line > 0; --line) {
        const size_t end = text.find('\n', size_t(start));
        if (end == std::string::npos) return false;
        start = (long long)end + 1;
    }
    const size_t end = std::min(text.find('\n', size_t(start)), text.size());
    const long long cell = font_x / kCellWidth;
    if (cell >= (long long)end - start) return false;
    return glyph_pixel(text[size_t(start + cell)], int(font_x % kCellWidth),
                       int(font_y % kLineHeight));
}

// An RGBA image inside a larger buffer: guard bytes before and after it and
// padding at the end of every row (so the stride is not width * 4). Drawing
// must leave every guard byte as it was.
class Canvas {
public:
    static constexpr int kGuard = 64, kPad = 12;
    static constexpr uint8_t kGuardByte = 0xA5;

    Canvas(int width, int height, Rgba8 fill = {0, 0, 0, 255})
        : width_(width), height_(height), stride_(width * 4 + kPad),
          bytes_(size_t(2 * kGuard + stride_ * height), kGuardByte) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) set(x, y, fill);
    }

    ImageView view() { return {bytes_.data() + kGuard, width_, height_, stride_}; }
    uint8_t* at(int x, int y) { return bytes_.data() + kGuard + y * stride_ + x * 4; }
    void set(int x, int y, Rgba8 c) {
        uint8_t* p = at(x, y);
        p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = c.a;
    }
    bool lit(int x, int y) { return at(x, y)[0] != 0; }

    int lit_pixels() {
        int n = 0;
        for (int y = 0; y < height_; ++y)
            for (int x = 0; x < width_; ++x) n += lit(x, y);
        return n;
    }

    bool guards_intact() const {
        for (size_t i = 0; i < bytes_.size(); ++i) {
            const long long off = (long long)i - kGuard;
            const bool in_pixels = off >= 0 && off < (long long)stride_ * height_ &&
                                   off % stride_ < width_ * 4;
            if (!in_pixels && bytes_[i] != kGuardByte) return false;
        }
        return true;
    }

    // Pixels that differ from the reference, drawn over black in white.
    int mismatches(const std::string& text, long long x0, long long y0, int scale) {
        int bad = 0;
        for (int y = 0; y < height_; ++y)
            for (int x = 0; x < width_; ++x)
                bad += lit(x, y) != reference_lit(text, x0, y0, scale, x, y);
        return bad;
    }

private:
    int width_, height_, stride_;
    std::vector<uint8_t> bytes_;
};

}  // namespace

TEST_CASE("every printable glyph but space sets a pixel; space sets none", "[text]") {
    CHECK(lit_count(' ') == 0);
    for (int c = 33; c <= 126; ++c) {
        INFO("character " << char(c));
        CHECK(lit_count(char(c)) > 0);
    }
}

TEST_CASE("all 95 glyphs and the hollow box are pairwise distinct", "[text]") {
    std::set<std::string> seen;
    for (int c = 32; c <= 126; ++c) {
        INFO("character " << char(c) << " repeats an earlier glyph");
        CHECK(seen.insert(glyph_art(char(c))).second);
    }
    CHECK(seen.size() == 95);
    CHECK(seen.count(glyph_art('\x01')) == 0);
}

TEST_CASE("descenders reach rows 7-8; capitals and digits stay above the baseline",
          "[text]") {
    for (char c : std::string("gjpqy")) {
        INFO("character " << c);
        CHECK(lit_in_rows(c, kGlyphAscent, kGlyphHeight - 1) > 0);
    }
    for (char c : std::string("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789abcdefhiklmnorstuvwxz")) {
        INFO("character " << c);
        CHECK(lit_in_rows(c, kGlyphAscent, kGlyphHeight - 1) == 0);
    }
    for (char c : std::string("acemnorsuvwxz")) {  // no ascender: x-height only
        INFO("character " << c);
        CHECK(lit_in_rows(c, 0, 1) == 0);
    }
}

TEST_CASE("glyph_pixel is false outside the glyph", "[text]") {
    for (int c = 0; c < 256; ++c) {
        for (int row = -1; row <= kLineHeight; ++row) {
            CHECK_FALSE(glyph_pixel(char(c), -1, row));
            CHECK_FALSE(glyph_pixel(char(c), kGlyphWidth, row));
        }
        CHECK_FALSE(glyph_pixel(char(c), 0, kGlyphHeight));
    }
}

TEST_CASE("drawing \"Hi\" sets exactly the glyph table's pixels", "[text]") {
    const std::string hi = "Hi";
    const int lit = lit_count('H') + lit_count('i');
    {
        Canvas canvas(16, 13);
        draw_text(canvas.view(), 3, 2, hi, kWhite);
        CHECK(canvas.mismatches(hi, 3, 2, 1) == 0);
        CHECK(canvas.lit_pixels() == lit);
        CHECK(canvas.lit(3, 2));    // H's top-left stroke
        CHECK(canvas.lit(9 + 2, 2));  // i's dot, one cell to the right
        const uint8_t* p = canvas.at(3, 2);
        CHECK((p[0] == 255 && p[1] == 255 && p[2] == 255 && p[3] == 255));
        CHECK(canvas.guards_intact());
    }
    {
        Canvas canvas(30, 24);
        draw_text(canvas.view(), 1, 3, hi, kWhite, 2);
        CHECK(canvas.mismatches(hi, 1, 3, 2) == 0);
        CHECK(canvas.lit_pixels() == 4 * lit);
        CHECK(canvas.guards_intact());
    }
}

TEST_CASE("'\\n' returns to the start column one line down", "[text]") {
    const std::string text = "ab\n\ny!";
    Canvas canvas(20, 40);
    draw_text(canvas.view(), 2, 1, text, kWhite);
    CHECK(canvas.mismatches(text, 2, 1, 1) == 0);
    CHECK(canvas.lit_pixels() == lit_count('a') + lit_count('b') + lit_count('y') +
                                     lit_count('!'));
}

TEST_CASE("text_width and text_height measure the widest line and the line count",
          "[text]") {
    CHECK(text_width("", 1) == 0);
    CHECK(text_height("", 1) == 0);
    CHECK(text_width("abc") == 3 * kCellWidth);
    CHECK(text_height("abc") == kLineHeight);
    CHECK(text_width("ab\ncdef\nx", 1) == 4 * kCellWidth);
    CHECK(text_height("ab\ncdef\nx", 1) == 3 * kLineHeight);
    CHECK(text_width("ab\ncdef\nx", 3) == 3 * 4 * kCellWidth);
    CHECK(text_height("ab\ncdef\nx", 3) == 3 * 3 * kLineHeight);
    CHECK(text_height("one\n", 1) == 2 * kLineHeight);  // a trailing '\n' starts a line
    CHECK(text_width("\n\n", 2) == 0);
    CHECK(text_width("abc", 0) == text_width("abc", 1));  // scale below 1 counts as 1
}

TEST_CASE("drawing partly or wholly outside the image writes only inside it", "[text]") {
    const std::string text = "Clip {me}\ngjpqy \x80|";
    const int positions[][2] = {{-3, -4},   {-13, 2},  {4, 3},          {5, -8},
                                {0, 100},   {100, 0},  {-1000, -1000},  {6, 4},
                                {INT_MIN, INT_MIN}, {INT_MAX, INT_MAX}, {INT_MAX - 3, 0},
                                {-20, -10}};
    for (int scale : {1, 2, 3}) {
        for (const auto& pos : positions) {
            INFO("at " << pos[0] << ", " << pos[1] << ", scale " << scale);
            Canvas canvas(7, 5);
            draw_text(canvas.view(), pos[0], pos[1], text, kWhite, scale);
            CHECK(canvas.guards_intact());
            CHECK(canvas.mismatches(text, pos[0], pos[1], scale) == 0);
        }
    }
    Canvas canvas(7, 5);
    fill_rect(canvas.view(), INT_MIN, -5, INT_MAX, INT_MAX, kWhite);
    fill_rect(canvas.view(), 3, 2, INT_MAX, INT_MAX, kWhite);
    CHECK(canvas.guards_intact());
    draw_text({nullptr, 7, 5, 0}, 0, 0, text, kWhite);            // empty views: no-ops
    draw_text({canvas.view().rgba, 0, 5, 0}, 0, 0, text, kWhite);
    fill_rect({canvas.view().rgba, 7, 5, 8}, 0, 0, 7, 5, kWhite);  // stride < width * 4
    CHECK(canvas.guards_intact());
}

TEST_CASE("a byte outside printable ASCII draws the hollow box", "[text]") {
    const char* box[] = {"#####", "#...#", "#...#", "#...#", "#...#",
                         "#...#", "#####", ".....", "....."};
    for (char c : std::string("\xC3\x80\t\r\x7F\x01")) {
        Canvas canvas(kCellWidth + 2, kLineHeight + 2);
        draw_text(canvas.view(), 1, 1, std::string(1, c), kWhite);
        int bad = 0;
        for (int y = 0; y < kLineHeight + 2; ++y)
            for (int x = 0; x < kCellWidth + 2; ++x) {
                const int col = x - 1, row = y - 1;
                const bool want = col >= 0 && col < kGlyphWidth && row >= 0 &&
                                  row < kGlyphHeight && box[row][col] == '#';
                bad += canvas.lit(x, y) != want;
            }
        INFO("byte " << int(static_cast<unsigned char>(c)));
        CHECK(bad == 0);
    }
}

TEST_CASE("fill_rect blends over the image in 8-bit space, within its rectangle", "[text]") {
    const Rgba8 under{200, 100, 0, 255};
    Canvas canvas(6, 5, under);
    const Rgba8 over{0, 50, 250, 128};
    fill_rect(canvas.view(), 1, 2, 3, 2, over);
    const double a = 128.0 / 255.0;
    const uint8_t* p = canvas.at(2, 3);
    CHECK(std::abs(p[0] - (0 * a + 200 * (1 - a))) <= 1.0);
    CHECK(std::abs(p[1] - (50 * a + 100 * (1 - a))) <= 1.0);
    CHECK(std::abs(p[2] - (250 * a + 0 * (1 - a))) <= 1.0);
    CHECK(p[3] == 255);
    int changed = 0;
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 6; ++x) changed += canvas.at(x, y)[0] != under.r;
    CHECK(changed == 3 * 2);
    CHECK(canvas.guards_intact());

    Canvas clear(2, 2, {10, 20, 30, 0});
    fill_rect(clear.view(), 0, 0, 2, 2, {250, 250, 250, 128});
    CHECK(std::abs(clear.at(1, 1)[3] - 128) <= 1);  // alpha: a + old * (1 - a)
    fill_rect(clear.view(), 0, 0, 2, 2, {7, 8, 9, 255});
    CHECK((clear.at(0, 0)[0] == 7 && clear.at(0, 0)[1] == 8 && clear.at(0, 0)[2] == 9));
    fill_rect(clear.view(), 0, 0, 2, 2, {255, 255, 255, 0});
    CHECK(clear.at(0, 0)[0] == 7);  // a = 0 draws nothing
}

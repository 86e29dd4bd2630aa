// The built-in 5x9 bitmap font and the blending rectangle fill that draws
// it. The font is a table of ASCII art, turned into bit rows at compile
// time, so drawing reads constant data and never allocates.
#include "facet/text.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cstddef>

namespace facet {

namespace {

constexpr int kFirstChar = 32;   // ' '
constexpr int kLastChar = 126;   // '~'
constexpr int kGlyphCount = kLastChar - kFirstChar + 1;
constexpr int kGlyphsPerBand = 8;
constexpr int kSlotWidth = kGlyphWidth + 1;  // a glyph and the space after it

// One glyph as bit rows, top first; bit (kGlyphWidth - 1 - col) is column col.
using GlyphRows = std::array<uint8_t, kGlyphHeight>;

// The font, as art: each band holds kGlyphsPerBand consecutive characters
// side by side, one string per glyph row, glyphs separated by one space.
// '#' is a set pixel, '.' a clear one. Rows 0..6 stand on the baseline,
// rows 7..8 hold descenders, lowercase letters are rows 2..6 tall.
struct Band {
    const char* rows[kGlyphHeight];
};

constexpr Band kBands[] = {
    //       !     "     #     $     %     &     '
    {{
        "..... ..#.. .#.#. .#.#. ..#.. ##... .#... ..#..",
        "..... ..#.. .#.#. .#.#. .#### ##..# #.#.. ..#..",
        "..... ..#.. .#.#. ##### #.#.. ...#. #.#.. ..#..",
        "..... ..#.. ..... .#.#. .###. ..#.. .#... .....",
        "..... ..#.. ..... ##### ..#.# .#... #.#.# .....",
        "..... ..... ..... .#.#. ####. #..## #..#. .....",
        "..... ..#.. ..... .#.#. ..#.. ...## .##.# .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // (     )     *     +     ,     -     .     /
    {{
        "...#. .#... ..... ..... ..... ..... ..... ....#",
        "..#.. ..#.. ..#.. ..#.. ..... ..... ..... ....#",
        ".#... ...#. #.#.# ..#.. ..... ..... ..... ...#.",
        ".#... ...#. .###. ##### ..... ##### ..... ..#..",
        ".#... ...#. #.#.# ..#.. ..... ..... ..... .#...",
        "..#.. ..#.. ..#.. ..#.. .##.. ..... .##.. #....",
        "...#. .#... ..... ..... .##.. ..... .##.. #....",
        "..... ..... ..... ..... ..#.. ..... ..... .....",
        "..... ..... ..... ..... .#... ..... ..... .....",
    }},
    // 0     1     2     3     4     5     6     7
    {{
        ".###. ..#.. .###. ##### ...#. ##### ..##. #####",
        "#...# .##.. #...# ...#. ..##. #.... .#... ....#",
        "#..## ..#.. ....# ..#.. .#.#. ####. #.... ...#.",
        "#.#.# ..#.. ...#. ...#. #..#. ....# ####. ..#..",
        "##..# ..#.. ..#.. ....# ##### ....# #...# .#...",
        "#...# ..#.. .#... #...# ...#. #...# #...# .#...",
        ".###. .###. ##### .###. ...#. .###. .###. .#...",
        "..... ..... ..... ..... ..... ..... ..... .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // 8     9     :     ;     <     =     >     ?
    {{
        ".###. .###. ..... ..... ...#. ..... .#... .###.",
        "#...# #...# .##.. .##.. ..#.. ..... ..#.. #...#",
        "#...# #...# .##.. .##.. .#... ##### ...#. ....#",
        ".###. .#### ..... ..... #.... ..... ....# ...#.",
        "#...# ....# ..... ..... .#... ##### ...#. ..#..",
        "#...# ...#. .##.. .##.. ..#.. ..... ..#.. .....",
        ".###. .##.. .##.. .##.. ...#. ..... .#... ..#..",
        "..... ..... ..... ..#.. ..... ..... ..... .....",
        "..... ..... ..... .#... ..... ..... ..... .....",
    }},
    // @     A     B     C     D     E     F     G
    {{
        ".###. .###. ####. .###. ####. ##### ##### .###.",
        "#...# #...# #...# #...# #...# #.... #.... #...#",
        "#.### #...# #...# #.... #...# #.... #.... #....",
        "#.#.# ##### ####. #.... #...# ####. ####. #.###",
        "#.### #...# #...# #.... #...# #.... #.... #...#",
        "#.... #...# #...# #...# #...# #.... #.... #...#",
        ".#### #...# ####. .###. ####. ##### #.... .####",
        "..... ..... ..... ..... ..... ..... ..... .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // H     I     J     K     L     M     N     O
    {{
        "#...# .###. ..### #...# #.... #...# #...# .###.",
        "#...# ..#.. ...#. #..#. #.... ##.## #...# #...#",
        "#...# ..#.. ...#. #.#.. #.... #.#.# ##..# #...#",
        "##### ..#.. ...#. ##... #.... #.#.# #.#.# #...#",
        "#...# ..#.. ...#. #.#.. #.... #...# #..## #...#",
        "#...# ..#.. #..#. #..#. #.... #...# #...# #...#",
        "#...# .###. .##.. #...# ##### #...# #...# .###.",
        "..... ..... ..... ..... ..... ..... ..... .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // P     Q     R     S     T     U     V     W
    {{
        "####. .###. ####. .#### ##### #...# #...# #...#",
        "#...# #...# #...# #.... ..#.. #...# #...# #...#",
        "#...# #...# #...# #.... ..#.. #...# #...# #...#",
        "####. #...# ####. .###. ..#.. #...# #...# #.#.#",
        "#.... #.#.# #.#.. ....# ..#.. #...# #...# #.#.#",
        "#.... #..#. #..#. ....# ..#.. #...# .#.#. #.#.#",
        "#.... .##.# #...# ####. ..#.. .###. ..#.. .#.#.",
        "..... ..... ..... ..... ..... ..... ..... .....",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // X     Y     Z     [     \     ]     ^     _
    {{
        "#...# #...# ##### .###. #.... .###. ..#.. .....",
        "#...# #...# ....# .#... #.... ...#. .#.#. .....",
        ".#.#. .#.#. ...#. .#... .#... ...#. #...# .....",
        "..#.. ..#.. ..#.. .#... ..#.. ...#. ..... .....",
        ".#.#. ..#.. .#... .#... ...#. ...#. ..... .....",
        "#...# ..#.. #.... .#... ....# ...#. ..... .....",
        "#...# ..#.. ##### .###. ....# .###. ..... .....",
        "..... ..... ..... ..... ..... ..... ..... #####",
        "..... ..... ..... ..... ..... ..... ..... .....",
    }},
    // `     a     b     c     d     e     f     g
    {{
        ".#... ..... #.... ..... ....# ..... ..##. .....",
        "..#.. ..... #.... ..... ....# ..... .#..# .....",
        "..... .###. #.##. .###. .##.# .###. .#... .####",
        "..... ....# ##..# #.... #..## #...# ###.. #...#",
        "..... .#### #...# #.... #...# ##### .#... #...#",
        "..... #...# #...# #...# #...# #.... .#... #...#",
        "..... .#### ####. .###. .#### .###. .#... .####",
        "..... ..... ..... ..... ..... ..... ..... ....#",
        "..... ..... ..... ..... ..... ..... ..... .###.",
    }},
    // h     i     j     k     l     m     n     o
    {{
        "#.... ..#.. ...#. #.... .##.. ..... ..... .....",
        "#.... ..... ..... #.... ..#.. ..... ..... .....",
        "#.##. .##.. ..##. #..#. ..#.. ##.#. #.##. .###.",
        "##..# ..#.. ...#. #.#.. ..#.. #.#.# ##..# #...#",
        "#...# ..#.. ...#. ##... ..#.. #.#.# #...# #...#",
        "#...# ..#.. ...#. #.#.. ..#.. #.#.# #...# #...#",
        "#...# .###. ...#. #..#. .###. #.#.# #...# .###.",
        "..... ..... #..#. ..... ..... ..... ..... .....",
        "..... ..... .##.. ..... ..... ..... ..... .....",
    }},
    // p     q     r     s     t     u     v     w
    {{
        "..... ..... ..... ..... .#... ..... ..... .....",
        "..... ..... ..... ..... .#... ..... ..... .....",
        "####. .#### #.##. .#### ###.. #...# #...# #...#",
        "#...# #...# ##..# #.... .#... #...# #...# #...#",
        "#...# #...# #.... .###. .#... #...# #...# #.#.#",
        "#...# #...# #.... ....# .#..# #..## .#.#. #.#.#",
        "####. .#### #.... ####. ..##. .##.# ..#.. .#.#.",
        "#.... ....# ..... ..... ..... ..... ..... .....",
        "#.... ....# ..... ..... ..... ..... ..... .....",
    }},
    // x     y     z     {     |     }     ~
    {{
        "..... ..... ..... ...## ..#.. ##... .....",
        "..... ..... ..... ..#.. ..#.. ..#.. .....",
        "#...# #...# ##### ..#.. ..#.. ..#.. .#...",
        ".#.#. #...# ...#. .#... ..#.. ...#. #.#.#",
        "..#.. #...# ..#.. ..#.. ..#.. ..#.. ...#.",
        ".#.#. #...# .#... ..#.. ..#.. ..#.. .....",
        "#...# .#### ##### ...## ..#.. ##... .....",
        "..... ....# ..... ..... ..... ..... .....",
        "..... .###. ..... ..... ..... ..... .....",
    }},
};
static_assert(std::size(kBands) == (kGlyphCount + kGlyphsPerBand - 1) / kGlyphsPerBand);

// Drawn for every byte that is not printable ASCII.
constexpr Band kBoxArt = {{
    "#####",
    "#...#",
    "#...#",
    "#...#",
    "#...#",
    "#...#",
    "#####",
    ".....",
    ".....",
}};

constexpr int length(const char* s) {
    int n = 0;
    while (s[n] != '\0') ++n;
    return n;
}

// Reads glyph `slot` of a band holding `glyphs` glyphs. A malformed table
// throws, which inside a constant expression is a compile error.
constexpr GlyphRows parse_glyph(const Band& band, int glyphs, int slot) {
    GlyphRows bits{};
    for (int row = 0; row < kGlyphHeight; ++row) {
        const char* text = band.rows[row];
        if (length(text) != glyphs * kSlotWidth - 1) throw "font art: row has the wrong length";
        for (int col = 0; col < kGlyphWidth; ++col) {
            const char ch = text[slot * kSlotWidth + col];
            if (ch != '#' && ch != '.') throw "font art: pixel is neither '#' nor '.'";
            bits[row] = uint8_t(bits[row] << 1 | (ch == '#'));
        }
        if (slot + 1 < glyphs && text[slot * kSlotWidth + kGlyphWidth] != ' ')
            throw "font art: glyphs must be separated by one space";
    }
    return bits;
}

constexpr std::array<GlyphRows, kGlyphCount> build_font() {
    std::array<GlyphRows, kGlyphCount> font{};
    for (int i = 0; i < kGlyphCount; ++i) {
        const int band = i / kGlyphsPerBand;
        const int glyphs = std::min(kGlyphsPerBand, kGlyphCount - band * kGlyphsPerBand);
        font[i] = parse_glyph(kBands[band], glyphs, i % kGlyphsPerBand);
    }
    return font;
}

constexpr std::array<GlyphRows, kGlyphCount> kFont = build_font();
constexpr GlyphRows kBox = parse_glyph(kBoxArt, 1, 0);

const GlyphRows& glyph_of(char c) {
    const int code = static_cast<unsigned char>(c);
    if (code < kFirstChar || code > kLastChar) return kBox;
    return kFont[code - kFirstChar];
}

// A half-open pixel rectangle [x0, x1) x [y0, y1), wide enough that no
// position or size a caller passes can overflow it.
struct Rect {
    int64_t x0, y0, x1, y1;
};

int64_t row_stride(const ImageView& image) {
    return image.stride == 0 ? int64_t(image.width) * 4 : image.stride;
}

bool is_empty(const ImageView& image) {
    return image.rgba == nullptr || image.width < 1 || image.height < 1 ||
           row_stride(image) < int64_t(image.width) * 4;
}

Rect clip(const ImageView& image, Rect r) {
    return {std::max<int64_t>(r.x0, 0), std::max<int64_t>(r.y0, 0),
            std::min<int64_t>(r.x1, image.width), std::min<int64_t>(r.y1, image.height)};
}

// (src * a + dst * (255 - a)) / 255, rounded to nearest; exact at a = 0 and 255.
uint8_t mix(int src, int dst, int a) {
    return uint8_t((src * a + dst * (255 - a) + 127) / 255);
}

// Blends color over every pixel of r; r must already be clipped to the image.
void fill_clipped(const ImageView& image, Rect r, Rgba8 color) {
    const size_t stride = size_t(row_stride(image));
    for (int64_t y = r.y0; y < r.y1; ++y) {
        uint8_t* p = image.rgba + size_t(y) * stride + size_t(r.x0) * 4;
        for (int64_t x = r.x0; x < r.x1; ++x, p += 4) {
            p[0] = mix(color.r, p[0], color.a);
            p[1] = mix(color.g, p[1], color.a);
            p[2] = mix(color.b, p[2], color.a);
            p[3] = mix(255, p[3], color.a);
        }
    }
}

bool overlaps(const ImageView& image, Rect r) {
    const Rect c = clip(image, r);
    return c.x0 < c.x1 && c.y0 < c.y1;
}

// Draws one glyph whose cell's top-left corner is (x, y); each set font
// pixel becomes a scale x scale block.
void draw_glyph(const ImageView& image, int64_t x, int64_t y, const GlyphRows& glyph,
                Rgba8 color, int64_t scale) {
    if (!overlaps(image, {x, y, x + kGlyphWidth * scale, y + kGlyphHeight * scale})) return;
    for (int row = 0; row < kGlyphHeight; ++row) {
        for (int col = 0; col < kGlyphWidth; ++col) {
            if ((glyph[row] >> (kGlyphWidth - 1 - col) & 1) == 0) continue;
            const int64_t px = x + col * scale, py = y + row * scale;
            const Rect block = clip(image, {px, py, px + scale, py + scale});
            if (block.x0 < block.x1 && block.y0 < block.y1) fill_clipped(image, block, color);
        }
    }
}

int clamp_to_int(int64_t v) { return int(std::min<int64_t>(v, INT_MAX)); }

}  // namespace

int text_width(std::string_view text, int scale) {
    int64_t widest = 0, line = 0;
    for (char c : text) {
        line = c == '\n' ? 0 : line + 1;
        widest = std::max(widest, line);
    }
    return clamp_to_int(widest * kCellWidth * std::max(scale, 1));
}

int text_height(std::string_view text, int scale) {
    if (text.empty()) return 0;
    const int64_t lines = 1 + std::count(text.begin(), text.end(), '\n');
    return clamp_to_int(lines * kLineHeight * std::max(scale, 1));
}

void draw_text(ImageView image, int x, int y, std::string_view text, Rgba8 color, int scale) {
    if (is_empty(image) || color.a == 0) return;
    const int64_t s = std::max(scale, 1);
    int64_t pen_x = x, pen_y = y;
    for (char c : text) {
        if (c == '\n') {
            pen_x = x;
            pen_y += kLineHeight * s;
            continue;
        }
        draw_glyph(image, pen_x, pen_y, glyph_of(c), color, s);
        pen_x += kCellWidth * s;
    }
}

void fill_rect(ImageView image, int x, int y, int w, int h, Rgba8 color) {
    if (is_empty(image) || color.a == 0 || w < 1 || h < 1) return;
    const Rect r = clip(image, {x, y, int64_t(x) + w, int64_t(y) + h});
    if (r.x0 < r.x1 && r.y0 < r.y1) fill_clipped(image, r, color);
}

bool glyph_pixel(char c, int col, int row) {
    if (col < 0 || col >= kGlyphWidth || row < 0 || row >= kGlyphHeight) return false;
    return (glyph_of(c)[row] >> (kGlyphWidth - 1 - col) & 1) != 0;
}

}  // namespace facet

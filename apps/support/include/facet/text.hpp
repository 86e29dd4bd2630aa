// Text and rectangles drawn straight into an 8-bit RGBA image, for overlays
// (frame statistics, labels, a help line) that a viewer wants to show without
// a GPU API or a font library.
//
// What it does: draws printable ASCII in one built-in 5x9 bitmap font, at any
// whole-number scale, alpha-blended over the image and clipped to it; fills
// alpha-blended rectangles; measures text so a caller can size a backdrop.
//
// What it does not do: no other fonts, no kerning, no proportional widths, no
// anti-aliasing, no UTF-8 decoding (each byte outside 32..126 is one hollow
// box), no tabs or '\r' handling (only '\n' is special), and no
// gamma-correct blending: colours mix in 8-bit sRGB space, as stored, which
// is fine for an overlay but not for anything that will be lit or filtered.
// It never allocates and never writes outside the image.
//
// Use:
//   std::vector<uint8_t> rgba = framebuffer.resolve_srgb8();
//   facet::ImageView image{rgba.data(), framebuffer.width(), framebuffer.height()};
//   const std::string msg = "frame 12.3 ms\ntriangles 5120";
//   facet::fill_rect(image, 4, 4, facet::text_width(msg, 2) + 4,
//                    facet::text_height(msg, 2) + 4, {0, 0, 0, 160});
//   facet::draw_text(image, 6, 6, msg, {255, 255, 255, 255}, 2);
//
// Font metrics, in font pixels (multiply by the scale for image pixels).
// Each character owns a cell kCellWidth x kLineHeight (6 x 11) whose
// top-left corner is at the pen; its glyph covers the cell's top-left
// kGlyphWidth x kGlyphHeight (5 x 9):
//   rows 0..6   capitals, digits, ascenders; the baseline is under row 6
//   rows 2..6   lowercase x-height
//   rows 7..8   descenders (g j p q y , ; _)
//   column 5 and rows 9..10 are always blank, so neighbouring characters
//   and lines never touch.
#pragma once

#include <cstdint>
#include <string_view>

namespace facet {

inline constexpr int kGlyphWidth = 5;    // columns per glyph
inline constexpr int kGlyphHeight = 9;   // rows per glyph: kGlyphAscent + 2 descender rows
inline constexpr int kGlyphAscent = 7;   // rows 0..6 stand on the baseline
inline constexpr int kCellWidth = 6;     // horizontal advance per character
inline constexpr int kLineHeight = 11;   // vertical advance per '\n'

// A colour in 8-bit sRGB with straight (not premultiplied) alpha; a = 255 is
// opaque, a = 0 draws nothing.
struct Rgba8 {
    uint8_t r, g, b, a;
};

// A borrowed view of an 8-bit RGBA image, row-major, top row first, 4 bytes
// per pixel in the order r, g, b, a. stride is the distance in bytes from one
// row to the next; 0 (the default) means tightly packed, width * 4. A view
// with a null pointer, a width or height below 1, or a nonzero stride below
// width * 4 is empty: drawing into it does nothing.
struct ImageView {
    uint8_t* rgba = nullptr;
    int width = 0;
    int height = 0;
    int stride = 0;
};

// Width in image pixels of the widest line of text: its character count times
// kCellWidth * scale (so it includes the blank column after the last glyph).
// Every byte except '\n' counts as one character. A scale below 1 counts as 1.
int text_width(std::string_view text, int scale = 1);

// Height in image pixels: lines * kLineHeight * scale, where text has one line
// more than it has '\n' characters (a trailing '\n' starts an empty line) and
// the empty string has none. A scale below 1 counts as 1.
int text_height(std::string_view text, int scale = 1);

// Draws text with the top-left corner of its first cell at (x, y). '\n'
// returns to x and moves down kLineHeight * scale; bytes 32..126 draw their
// glyph; every other byte draws a hollow box. Each font pixel becomes a
// scale x scale block (a scale below 1 counts as 1). Pixels are blended with
// color as in fill_rect; those outside the image are skipped, so x and y may
// be negative or past the edges.
void draw_text(ImageView image, int x, int y, std::string_view text, Rgba8 color,
               int scale = 1);

// Fills the w x h rectangle whose top-left corner is (x, y), clipped to the
// image. Each pixel becomes color over the old one, in 8-bit sRGB space:
//   rgb = (color.rgb * a + old.rgb * (255 - a)) / 255,
//   alpha = a + old.alpha * (255 - a) / 255, both rounded to nearest.
// A rectangle with w or h below 1 draws nothing.
void fill_rect(ImageView image, int x, int y, int w, int h, Rgba8 color);

// Whether font pixel (col, row) of character c is set; false outside the
// kGlyphWidth x kGlyphHeight glyph. Bytes outside 32..126 report the hollow
// box that draw_text draws for them. For tests and for callers who render
// the font some other way.
bool glyph_pixel(char c, int col, int row);

}  // namespace facet

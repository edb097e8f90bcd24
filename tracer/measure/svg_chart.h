// A small SVG writer for the measurement charts (compare's speed-against-error plot, bench's rates against
// grid size): a white page, printf-style elements, framed plot areas with axis titles, escaped text.
#pragma once

#include <cstdio>
#include <string>

namespace terracast {

// Text for SVG character data and attribute values.
std::string xmlEscaped(const std::string& text);

class SvgChart {
public:
    // Opens a `width` x `height` page with a white background, in 12-pixel sans-serif.
    SvgChart(double width, double height);

    // Appends one printf-formatted piece of markup.
    template <class... Args>
    void add(const char* format, Args... args) {
        const int n = std::snprintf(nullptr, 0, format, args...);
        if (n <= 0) return;
        std::string piece(size_t(n) + 1, '\0');
        std::snprintf(piece.data(), piece.size(), format, args...);
        piece.pop_back();
        text_ += piece;
    }
    // Appends markup as it is.
    void raw(const std::string& markup) { text_ += markup; }

    // The black frame of a plot area.
    void frame(double x, double y, double width, double height);
    // An axis title centred under the plot at (x, y), or written upwards along the y axis at (x, y).
    void xTitle(double x, double y, const std::string& title);
    void yTitle(double x, double y, const std::string& title);

    // The finished document.
    std::string finish() const { return text_ + "</svg>\n"; }

private:
    std::string text_;
};

}  // namespace terracast

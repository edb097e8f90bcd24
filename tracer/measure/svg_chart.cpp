#include "tracer/measure/svg_chart.h"

namespace terracast {

std::string xmlEscaped(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

SvgChart::SvgChart(double width, double height) {
    add("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" viewBox=\"0 0 %.0f %.0f\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
        width, height, width, height);
}

void SvgChart::frame(double x, double y, double width, double height) {
    add("<rect x=\"%.0f\" y=\"%.0f\" width=\"%.0f\" height=\"%.0f\" fill=\"none\" stroke=\"black\"/>\n", x, y, width,
        height);
}

void SvgChart::xTitle(double x, double y, const std::string& title) {
    add("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">%s</text>\n", x, y, xmlEscaped(title).c_str());
}

void SvgChart::yTitle(double x, double y, const std::string& title) {
    add("<text transform=\"translate(%.0f %.0f) rotate(-90)\" text-anchor=\"middle\">%s</text>\n", x, y,
        xmlEscaped(title).c_str());
}

}  // namespace terracast

// The measurements' SVG writer: well-formed XML (read back by expat) whatever the text, and long markup kept
// whole.
#include "tracer/measure/svg_chart.h"

#include <catch2/catch.hpp>
#include <expat.h>

#include <string>

using namespace terracast;

namespace {

bool wellFormed(const std::string& text) {
    XML_Parser p = XML_ParserCreate(nullptr);
    const bool ok = XML_Parse(p, text.data(), int(text.size()), 1) == XML_STATUS_OK;
    XML_ParserFree(p);
    return ok;
}

}  // namespace

TEST_CASE("SVG chart: text is escaped and the document is well-formed", "[tracer][measure]") {
    CHECK(xmlEscaped("a<b & \"c\" > d") == "a&lt;b &amp; &quot;c&quot; &gt; d");
    SvgChart svg(300, 200);
    svg.frame(10, 10, 280, 180);
    svg.xTitle(150, 195, "rays < 1e6 & \"fast\"");
    svg.yTitle(5, 100, "error > 0");
    svg.add("<text x=\"%.0f\" y=\"%.0f\">%s</text>\n", 20.0, 30.0, xmlEscaped("AMD <Ryzen> & co").c_str());
    // Markup longer than any fixed buffer stays whole.
    std::string points;
    for (int k = 0; k < 400; ++k) points += std::to_string(k) + "," + std::to_string(k % 7) + " ";
    svg.add("<polyline fill=\"none\" stroke=\"black\" points=\"%s\"/>\n", points.c_str());
    const std::string text = svg.finish();
    CHECK(wellFormed(text));
    CHECK(text.find(points) != std::string::npos);
    CHECK(text.find("width=\"300\" height=\"200\"") != std::string::npos);
    CHECK(text.rfind("</svg>\n") == text.size() - 7);
}

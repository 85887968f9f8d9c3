// study/report_html.h: half floats and base64 against their definitions, and the page's data escaping
// (the answer's intervals: test_study_intervals.cpp).
#include "study/report_html.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace symphong {
namespace {

TEST(Half, EveryHalfRoundTripsAndMatchesItsDefinition) {
    for (unsigned h = 0; h < 65536; ++h) {
        const int e = (h >> 10) & 31, m = h & 1023;
        if (e == 31 && m) continue;  // NaN
        const double s = (h & 0x8000) ? -1 : 1;
        const double v = e == 31 ? s * INFINITY : e == 0 ? s * std::ldexp(m / 1024.0, -14) : s * std::ldexp(1 + m / 1024.0, e - 15);
        ASSERT_EQ(static_cast<double>(floatOfHalf(static_cast<std::uint16_t>(h))), v) << h;
        ASSERT_EQ(halfOf(static_cast<float>(v)), h) << h;
    }
}

TEST(Half, RoundsToNearestEvenAndOverflows) {
    EXPECT_EQ(halfOf(1.0f), 0x3c00);
    EXPECT_EQ(halfOf(65504.0f), 0x7bff);
    EXPECT_EQ(halfOf(65519.0f), 0x7bff);
    EXPECT_EQ(halfOf(65520.0f), 0x7c00);                 // the midpoint to 65536 rounds to even: infinity
    EXPECT_EQ(halfOf(1.0f + 1.0f / 2048), 0x3c00);       // halfway between 1 and 1 + 2^-10: even (1)
    EXPECT_EQ(halfOf(1.0f + 3.0f / 2048), 0x3c02);       // halfway between 1 + 2^-10 and 1 + 2^-9: even
    EXPECT_EQ(halfOf(1.0f + 1.5f / 2048), 0x3c01);       // above halfway
    EXPECT_EQ(halfOf(std::ldexp(1.0f, -25)), 0x0000);    // half the smallest subnormal: even (0)
    EXPECT_EQ(halfOf(std::ldexp(3.0f, -25)), 0x0002);    // 1.5 subnormal steps: even (2)
    EXPECT_EQ(halfOf(-2.0f), 0xc000);
    EXPECT_EQ(halfOf(1e-10f), 0x0000);
    EXPECT_TRUE(std::isnan(floatOfHalf(halfOf(NAN))));
}

TEST(Base64, RfcTestVectors) {  // RFC 4648, section 10
    const auto b = [](const std::string& s) { return base64(reinterpret_cast<const unsigned char*>(s.data()), s.size()); };
    EXPECT_EQ(b(""), "");
    EXPECT_EQ(b("f"), "Zg==");
    EXPECT_EQ(b("fo"), "Zm8=");
    EXPECT_EQ(b("foo"), "Zm9v");
    EXPECT_EQ(b("foob"), "Zm9vYg==");
    EXPECT_EQ(b("fooba"), "Zm9vYmE=");
    EXPECT_EQ(b("foobar"), "Zm9vYmFy");
    const unsigned char high[] = {0xfb, 0xff, 0xfe};
    EXPECT_EQ(base64(high, 3), "+//+");
}

TEST(ReportHtml, DataCannotCloseItsScript) {
    const std::string page = reportHtml({{"title", "</script><script>alert(1)</script>"}});
    EXPECT_EQ(page.find("</script><script>alert"), std::string::npos);
    EXPECT_NE(page.find("\\u003c/script>\\u003cscript>alert(1)\\u003c/script>"), std::string::npos);
    const std::string comment = reportHtml({{"title", "<!--<script>"}});
    EXPECT_EQ(comment.find("<!--<script>"), std::string::npos);
    EXPECT_EQ(page.find("@STUDY_DATA@"), std::string::npos);
    EXPECT_EQ(page.find("http://"), std::string::npos) << "no address outside the page";
    EXPECT_EQ(page.find("https://"), std::string::npos) << "no address outside the page";
}

}  // namespace
}  // namespace symphong

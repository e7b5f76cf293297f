// motorsim's CSV number format (sim/motorsim/num_format.h): format_g10 must
// write exactly what std::to_chars(general, 10) writes, for every double.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "motorsim/num_format.h"

namespace {

std::string fast(double v)
{
    char buf[mcsim::kG10MaxChars + 8];
    char* end = mcsim::format_g10(buf, v);
    return std::string(buf, end);
}

std::string reference(double v)
{
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 10);
    return std::string(buf, r.ptr);
}

TEST(NumFormat, NonFinite)
{
    EXPECT_EQ(fast(std::numeric_limits<double>::quiet_NaN()), "nan");
    EXPECT_EQ(fast(-std::numeric_limits<double>::quiet_NaN()), "nan");
    EXPECT_EQ(fast(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(fast(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(NumFormat, EdgeCases)
{
    const double cases[] = {0.0,
                            -0.0,
                            1.0,
                            -1.0,
                            0.5,
                            10.0,
                            1e9,
                            1e10,
                            9999999999.0,
                            9999999999.4,
                            9999999999.5,
                            9999999999.6,
                            1234567890.5,
                            0.1,
                            0.2,
                            1.0 / 3.0,
                            2.0 / 3.0,
                            1e-4,
                            9.99999999949e-5,
                            9.99999999951e-5,
                            1e-5,
                            0.00012345678905,
                            0.000285347802,
                            123456.7890123,
                            4.25,
                            42500.0,
                            3.14159265358979,
                            1e-12,
                            9.9999999999e-13,
                            1e31,
                            9.99999999e30,
                            1e-300,
                            1e300,
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::denorm_min(),
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::epsilon(),
                            static_cast<double>(0.1f),
                            static_cast<double>(2.99999991f)};
    for (double v : cases) {
        EXPECT_EQ(fast(v), reference(v)) << "v = " << reference(v);
        EXPECT_EQ(fast(-v), reference(-v)) << "v = " << reference(-v);
    }
}

// Every power of ten and the values around it, and ties at the 10th digit.
TEST(NumFormat, DecadeBoundariesAndTies)
{
    for (int e = -20; e <= 35; ++e) {
        const double p = std::pow(10.0, e);
        double lo = p, hi = p;
        for (int k = 0; k < 40; ++k) {
            ASSERT_EQ(fast(lo), reference(lo));
            ASSERT_EQ(fast(hi), reference(hi));
            lo = std::nextafter(lo, 0.0);
            hi = std::nextafter(hi, INFINITY);
        }
        // d.ddddddddd5 x 10^e: as close to a tie as a double gets.
        std::mt19937_64 g(static_cast<std::uint64_t>(e + 100));
        for (int k = 0; k < 2000; ++k) {
            const double m = 1e9 + static_cast<double>(g() % 9000000000ull) + 0.5;
            const double v = m * std::pow(10.0, e - 9);
            for (double w : {v, std::nextafter(v, 0.0), std::nextafter(v, INFINITY)}) {
                ASSERT_EQ(fast(w), reference(w)) << std::hexfloat << w;
            }
        }
    }
}

TEST(NumFormat, RandomValues)
{
    std::mt19937_64 g(12345);
    std::normal_distribution<double> n(0.0, 1.0);
    std::uniform_int_distribution<int> ex(-16, 34);
    for (int k = 0; k < 2000000; ++k) {
        double v = 0.0;
        switch (k % 4) {
        case 0:  // any bit pattern
        {
            const std::uint64_t b = g();
            std::memcpy(&v, &b, sizeof v);
            break;
        }
        case 1:  // the magnitudes of a simulation log
            v = n(g) * std::pow(10.0, ex(g));
            break;
        case 2:  // float telemetry widened to double
            v = static_cast<double>(static_cast<float>(n(g) * 10.0));
            break;
        default:  // short decimals (t_s = k * Ts)
            v = static_cast<double>(g() % 10000000) * 1e-4;
            break;
        }
        if (std::isfinite(v)) {  // NaN: "nan" whatever its sign (NonFinite)
            ASSERT_EQ(fast(v), reference(v)) << std::hexfloat << v;
        }
    }
}

}  // namespace

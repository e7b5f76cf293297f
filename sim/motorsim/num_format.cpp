#include "motorsim/num_format.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace mcsim {
namespace {

// Powers of ten that are exact in a double.
constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                               1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

constexpr char kPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// The two digits of 0 <= n < 100 in kPairs.
inline const char* pair(std::uint32_t n) { return kPairs + 2 * static_cast<std::size_t>(n); }

// a * 10^(9 - e10) with a single rounding: the power is exact, |9 - e10| <= 22.
inline double scale(double a, int e10) { return e10 <= 9 ? a * kPow10[9 - e10] : a / kPow10[e10 - 9]; }

// The 10 decimal digits of 1e9 <= m < 1e10 into d[0..9].
inline void put_10_digits(char* d, std::uint64_t m)
{
    std::uint32_t hi = static_cast<std::uint32_t>(m / 100000u);  // d[0..4]
    std::uint32_t lo = static_cast<std::uint32_t>(m % 100000u);  // d[5..9]
    std::memcpy(d + 8, pair(lo % 100u), 2);
    lo /= 100u;
    std::memcpy(d + 6, pair(lo % 100u), 2);
    d[5] = static_cast<char>('0' + lo / 100u);
    std::memcpy(d + 3, pair(hi % 100u), 2);
    hi /= 100u;
    std::memcpy(d + 1, pair(hi % 100u), 2);
    d[0] = static_cast<char>('0' + hi / 100u);
}

char* slow_g10(char* p, double v)
{
    return std::to_chars(p, p + kG10MaxChars, v, std::chars_format::general, 10).ptr;
}

}  // namespace

char* format_g10(char* p, double v)
{
    if (!std::isfinite(v)) {
        const char* s = std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
        const std::size_t n = std::strlen(s);
        // NOLINTNEXTLINE(bugprone-not-null-terminated-result): p is a CSV field, not a C string; the caller ends it
        std::memcpy(p, s, n);
        return p + n;
    }
    const double a = std::fabs(v);
    // Outside this range (zero and -0 included) the exponent does not fit the
    // table of exact powers of ten.
    if (!(a >= 1e-12 && a < 1e31)) {
        return slow_g10(p, v);
    }
    // a in [2^(e2-1), 2^e2): floor(log10 a) is e10 or e10 + 1.
    std::uint64_t bits = 0;
    std::memcpy(&bits, &a, sizeof bits);
    const int e2 = static_cast<int>((bits >> 52) & 0x7ff) - 1022;
    // floor((e2 - 1) * log10(2)); >> of a negative int is an arithmetic shift in GCC and Clang.
    int e10 = ((e2 - 1) * 78913) >> 18;
    double s = scale(a, e10);
    if (s >= 1e10) {
        ++e10;
        s = scale(a, e10);
    }
    // s is within half an ulp (< 1e-6 below 1e10) of the exact a * 10^(9 - e10):
    // round half up unless the fraction is too close to 1/2 to tell.
    const auto whole = static_cast<std::uint64_t>(s);
    const double frac = s - static_cast<double>(whole);
    if (std::fabs(frac - 0.5) < 1e-5) {
        return slow_g10(p, v);
    }
    std::uint64_t m = whole + (frac > 0.5 ? 1u : 0u);
    if (m >= 10000000000u) {  // 9999999999.5 and up rounds to 1.000000000e(e10 + 1)
        m /= 10u;
        ++e10;
    } else if (m < 1000000000u) {
        return slow_g10(p, v);  // not reached: s >= 1e9 - 1e-6 rounds to >= 1e9
    }
    char d[10];
    put_10_digits(d, m);
    int nd = 10;
    while (nd > 1 && d[nd - 1] == '0') {
        --nd;
    }

    if (v < 0) {
        *p++ = '-';
    }
    if (e10 < -4 || e10 >= 10) {  // d.ddde-05, as printf's %g
        *p++ = d[0];
        if (nd > 1) {
            *p++ = '.';
            std::memcpy(p, d + 1, static_cast<std::size_t>(nd - 1));
            p += nd - 1;
        }
        *p++ = 'e';
        int x = e10;
        *p++ = x < 0 ? '-' : '+';
        x = x < 0 ? -x : x;  // 5 <= |x| <= 31 here
        std::memcpy(p, pair(static_cast<std::uint32_t>(x)), 2);
        return p + 2;
    }
    if (e10 >= 0) {  // ddd or ddd.ddd
        const int ip = e10 + 1;
        std::memcpy(p, d, static_cast<std::size_t>(ip));
        p += ip;
        if (nd > ip) {
            *p++ = '.';
            std::memcpy(p, d + ip, static_cast<std::size_t>(nd - ip));
            p += nd - ip;
        }
        return p;
    }
    *p++ = '0';  // 0.000ddd
    *p++ = '.';
    for (int k = 0; k < -e10 - 1; ++k) {
        *p++ = '0';
    }
    std::memcpy(p, d, static_cast<std::size_t>(nd));
    return p + nd;
}

}  // namespace mcsim

// num_format.h - fast number formatting for motorsim's CSV log.
#ifndef MCSIM_MOTORSIM_NUM_FORMAT_H
#define MCSIM_MOTORSIM_NUM_FORMAT_H

#include <cstddef>

namespace mcsim {

// Longest output of format_g10: "-1.234567891e-300".
constexpr std::size_t kG10MaxChars = 24;

// Writes v with 10 significant digits, byte for byte what
// std::to_chars(p, p + kG10MaxChars, v, std::chars_format::general, 10)
// writes (printf's %.10g without trailing zeros), and "nan", "inf", "-inf"
// for the non-finite values; returns the end of the text. The common case is
// integer arithmetic on the digits (~3x faster than to_chars' general path);
// values it cannot round exactly (ties, extreme exponents) go to to_chars.
char* format_g10(char* p, double v);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_NUM_FORMAT_H

// mc_convert.h - conversions between the firmware numeric type mc_t
// (firmware/math/mc_num.h) and double for the simulator and the software
// plant backend. Values are SI in both builds; only the representation
// differs: a cast in the float build, ldexp by MC_FRAC_BITS with rounding
// and saturation in the fixed-point build. The arithmetic itself lives in
// firmware/math/mc_convert.h (shared with the gain design) so the two sides
// cannot disagree on the scaling.
#ifndef MCSIM_MC_CONVERT_H
#define MCSIM_MC_CONVERT_H

#include "math/mc_convert.h"
#include "math/mc_num.h"

namespace mcsim {

inline mc_t to_mc(double x)
{
    // NaN has no fixed-point image; treat it as 0 in both builds so a
    // broken plant value cannot become a saturated command.
    return (x == x) ? mc_from_double(x) : mc_from_double(0.0);
}

inline double to_double(mc_t x) { return mc_to_double(x); }

}  // namespace mcsim

#endif  // MCSIM_MC_CONVERT_H

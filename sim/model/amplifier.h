// amplifier.h - the two linear power amplifiers of the test bench (section
// 5.3): each phase follows its command up to the supply, |v| <= V_max.
#ifndef MCSIM_MODEL_AMPLIFIER_H
#define MCSIM_MODEL_AMPLIFIER_H

namespace mcsim {

struct Amplifier {
    double v_max_V = 30.0;

    double apply(double v_cmd_V) const
    {
        if (v_cmd_V > v_max_V) {
            return v_max_V;
        }
        if (v_cmd_V < -v_max_V) {
            return -v_max_V;
        }
        // NaN commands (a broken controller) give 0 V, never a NaN plant.
        return (v_cmd_V == v_cmd_V) ? v_cmd_V : 0.0;
    }
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_AMPLIFIER_H

// drive_signals.h - a drive's signals (firmware/drives/drive.h:
// drive_signal_t, the operations signals and read_signals) as motorsim's
// recorder takes them: the list the drive gives after init, checked once
// (names unique and well-formed, units given, at most DRIVE_SIGNALS_MAX),
// the values after each step in double, and a signal found by name. A
// metric that needs a drive's quantity asks for its signal here and is left
// out when the drive has none; nothing in motorsim looks into a drive's
// state.
#ifndef MCSIM_MOTORSIM_DRIVE_SIGNALS_H
#define MCSIM_MOTORSIM_DRIVE_SIGNALS_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "motorsim/metrics.h"

extern "C" {
#include "drives/drive.h"
}

namespace mcsim {

class DriveSignals {
public:
    // The list of d after its init. Throws std::logic_error naming the
    // drive and the signal when the list is malformed.
    explicit DriveSignals(const drive_t& d);

    std::size_t size() const { return n_; }
    const drive_signal_t& at(std::size_t k) const { return list_[k]; }
    // The index of the signal of that name, or -1.
    int find(const char* name) const;
    // The indices of the signals that are a column of the log (not
    // settings), in the drive's order.
    std::vector<int> columns() const;

    // Reads every value after a step (or init); value(k) is then signal k's.
    void read();
    double value(int k) const { return v_[static_cast<std::size_t>(k)]; }

    // The signal of that name read now, as the metric `metric` (an integer
    // signal as an integer) appended to *m; nothing when the drive has no
    // such signal.
    void append_metric(MetricList* m, const char* metric, const char* signal) const;

private:
    drive_t drive_;
    const drive_signal_t* list_ = nullptr;
    std::size_t n_ = 0;
    std::array<double, DRIVE_SIGNALS_MAX> v_{};
};

// The first problem of a signal list (its count, a name, a unit, a
// description, a name listed twice), or "" when it is well-formed.
std::string signal_list_problem(const drive_signal_t* list, std::uint32_t n);

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_DRIVE_SIGNALS_H

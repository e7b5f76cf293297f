// metrics.h - a run's metrics: (name, value) pairs in the order they are
// printed and written (outputs.h), each an integer or a double.
#ifndef MCSIM_MOTORSIM_METRICS_H
#define MCSIM_MOTORSIM_METRICS_H

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace mcsim {

using MetricValue = std::variant<std::int64_t, double>;
using MetricList = std::vector<std::pair<std::string, MetricValue>>;

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_METRICS_H

#include "motorsim/drive_signals.h"

#include <cctype>
#include <cstring>
#include <stdexcept>

#include "mc_convert.h"

namespace mcsim {

std::string signal_list_problem(const drive_signal_t* list, std::uint32_t n)
{
    if (n > DRIVE_SIGNALS_MAX) {
        return std::to_string(n) + " signals, more than DRIVE_SIGNALS_MAX";
    }
    if (n > 0 && list == nullptr) {
        return "no list for " + std::to_string(n) + " signals";
    }
    for (std::uint32_t k = 0; k < n; ++k) {
        const drive_signal_t& s = list[k];
        const std::string at = "signal " + std::to_string(k);
        if (s.name == nullptr || s.name[0] == '\0' || std::isalpha(static_cast<unsigned char>(s.name[0])) == 0) {
            return at + ": a name must start with a letter";
        }
        for (const char* c = s.name; *c != '\0'; ++c) {
            if (std::isalnum(static_cast<unsigned char>(*c)) == 0 && *c != '_') {
                return at + " '" + s.name + "': letters, digits and _ only";
            }
        }
        if (s.unit == nullptr || s.unit[0] == '\0') {
            return at + " '" + s.name + "': no unit (\"1\" when dimensionless)";
        }
        if (s.description == nullptr || s.description[0] == '\0') {
            return at + " '" + s.name + "': no description";
        }
        for (std::uint32_t j = 0; j < k; ++j) {
            if (std::strcmp(list[j].name, s.name) == 0) {
                return at + " '" + s.name + "': listed twice";
            }
        }
    }
    return "";
}

DriveSignals::DriveSignals(const drive_t& d) : drive_(d)
{
    std::uint32_t n = 0;
    list_ = drive_signals(&drive_, &n);
    const std::string why = signal_list_problem(list_, n);
    if (!why.empty()) {
        throw std::logic_error(std::string("the ") + d.ops->name + " drive's signals: " + why);
    }
    n_ = n;
}

int DriveSignals::find(const char* name) const
{
    for (std::size_t k = 0; k < n_; ++k) {
        if (std::strcmp(list_[k].name, name) == 0) {
            return static_cast<int>(k);
        }
    }
    return -1;
}

std::vector<int> DriveSignals::columns() const
{
    std::vector<int> c;
    for (std::size_t k = 0; k < n_; ++k) {
        if ((list_[k].flags & DRIVE_SIGNAL_SETTING) == 0) {
            c.push_back(static_cast<int>(k));
        }
    }
    return c;
}

void DriveSignals::read()
{
    std::array<mc_t, DRIVE_SIGNALS_MAX> raw{};
    drive_read_signals(&drive_, raw.data());
    for (std::size_t k = 0; k < n_; ++k) {
        v_[k] = to_double(raw[k]);
    }
}

void DriveSignals::append_metric(MetricList* m, const char* metric, const char* signal) const
{
    const int k = find(signal);
    if (k < 0) {
        return;
    }
    std::array<mc_t, DRIVE_SIGNALS_MAX> raw{};
    drive_read_signals(&drive_, raw.data());
    const double v = to_double(raw[static_cast<std::size_t>(k)]);
    if ((list_[k].flags & DRIVE_SIGNAL_INTEGER) != 0) {
        m->emplace_back(metric, static_cast<std::int64_t>(v));
    } else {
        m->emplace_back(metric, v);
    }
}

}  // namespace mcsim

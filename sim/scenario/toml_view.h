// toml_view.h - one TOML table of a scenario with its file and dotted key
// prefix, so that every error names both ("file: speed.profile_rpm: ...");
// typed getters that refuse a wrong type, unknown keys, non-finite numbers.
// Used by load_scenario (scenario.cpp) and by each drive's host part
// (sim/host_drives/), which parses its own scenario table with it.
#ifndef MCSIM_SCENARIO_TOML_VIEW_H
#define MCSIM_SCENARIO_TOML_VIEW_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "scenario/scenario.h"

namespace mcsim {

inline std::string fmt_num(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.6g", v);
    return buf;
}

inline const char* type_name(const toml::node& n)
{
    switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time: return "a date/time";
    default: return "nothing";
    }
}

[[noreturn]] inline void fail(const std::string& file, const std::string& key, const std::string& why)
{
    throw ScenarioError(file + ": " + key + ": " + why);
}

// A view of one TOML table that knows its file and its dotted key prefix,
// so every error can name both.
class View {
public:
    View(const toml::table& t, std::string file, std::string prefix)
        : t_(t), file_(std::move(file)), prefix_(std::move(prefix))
    {
    }

    std::string key(const std::string& k) const { return prefix_.empty() ? k : prefix_ + "." + k; }
    const std::string& file() const { return file_; }
    [[noreturn]] void fail(const std::string& k, const std::string& why) const { mcsim::fail(file_, key(k), why); }

    // Unknown keys first: a typo then reads "unknown key", not "missing".
    void only(const std::vector<std::string>& allowed) const
    {
        for (auto&& kv : t_) {
            const std::string k(kv.first.str());
            if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
                fail(k, "unknown key");
            }
        }
    }

    bool has(const std::string& k) const { return t_.contains(k); }
    const toml::table& raw() const { return t_; }

    std::vector<std::string> keys() const
    {
        std::vector<std::string> ks;
        for (auto&& kv : t_) {
            ks.emplace_back(kv.first.str());
        }
        return ks;
    }

    std::optional<double> number(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        double v = 0.0;
        if (n->is_floating_point()) {
            v = n->as_floating_point()->get();
        } else if (n->is_integer()) {
            v = static_cast<double>(n->as_integer()->get());
        } else {
            fail(k, std::string("expected a number (got ") + type_name(*n) + ")");
        }
        if (!std::isfinite(v)) {
            fail(k, "must be finite (got " + fmt_num(v) + ")");
        }
        return v;
    }

    double number_req(const std::string& k) const
    {
        const auto v = number(k);
        if (!v) {
            fail(k, "missing required field");
        }
        return *v;
    }

    std::optional<std::int64_t> integer(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_integer()) {
            fail(k, std::string("expected an integer (got ") + type_name(*n) + ")");
        }
        return n->as_integer()->get();
    }

    std::optional<bool> boolean(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_boolean()) {
            fail(k, std::string("expected true or false (got ") + type_name(*n) + ")");
        }
        return n->as_boolean()->get();
    }

    std::optional<std::string> string(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_string()) {
            fail(k, std::string("expected a string (got ") + type_name(*n) + ")");
        }
        return n->as_string()->get();
    }

    std::optional<View> table(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_table()) {
            fail(k, std::string("expected a table (got ") + type_name(*n) + ")");
        }
        return View(*n->as_table(), file_, key(k));
    }

    // An array whose elements must all be tables (inline or [[...]]).
    std::optional<std::vector<View>> tables(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_array()) {
            fail(k, std::string("expected an array of tables (got ") + type_name(*n) + ")");
        }
        std::vector<View> out;
        const toml::array& a = *n->as_array();
        for (std::size_t i = 0; i < a.size(); ++i) {
            const std::string ki = key(k) + "[" + std::to_string(i) + "]";
            if (!a[i].is_table()) {
                mcsim::fail(file_, ki, std::string("expected a table (got ") + type_name(a[i]) + ")");
            }
            out.emplace_back(*a[i].as_table(), file_, ki);
        }
        return out;
    }

    // An array of exactly n finite numbers, each checked by ok (its
    // index named on failure: "key[i]: why (got x)").
    std::optional<std::vector<double>> numbers(const std::string& k, std::size_t n, bool (*ok)(double),
                                               const std::string& why) const
    {
        const toml::node* node = t_.get(k);
        if (node == nullptr) {
            return std::nullopt;
        }
        const toml::array* a = node->as_array();
        if (a == nullptr || a->size() != n) {
            fail(k, "expected an array of " + std::to_string(n) + " numbers (got " +
                        (a == nullptr ? std::string(type_name(*node)) : std::to_string(a->size()) + " entries") + ")");
        }
        std::vector<double> out;
        for (std::size_t i = 0; i < n; ++i) {
            const toml::node& x = (*a)[i];
            const std::string ki = key(k) + "[" + std::to_string(i) + "]";
            if (!x.is_number()) {
                mcsim::fail(file_, ki, std::string("expected a number (got ") + type_name(x) + ")");
            }
            const double v = x.is_floating_point() ? x.as_floating_point()->get() : static_cast<double>(x.as_integer()->get());
            if (!std::isfinite(v) || !ok(v)) {
                mcsim::fail(file_, ki, why + " (got " + fmt_num(v) + ")");
            }
            out.push_back(v);
        }
        return out;
    }

    // An array of [a, b] number pairs (e.g. [[0.0, 0.0], [1.0, 50.0]]).
    std::optional<std::vector<std::pair<double, double>>> pairs(const std::string& k) const
    {
        const toml::node* n = t_.get(k);
        if (n == nullptr) {
            return std::nullopt;
        }
        if (!n->is_array()) {
            fail(k, std::string("expected an array of [number, number] pairs (got ") + type_name(*n) + ")");
        }
        std::vector<std::pair<double, double>> out;
        const toml::array& a = *n->as_array();
        for (std::size_t i = 0; i < a.size(); ++i) {
            const std::string ki = key(k) + "[" + std::to_string(i) + "]";
            const toml::array* e = a[i].as_array();
            if (e == nullptr || e->size() != 2) {
                mcsim::fail(file_, ki, "expected a pair [number, number]");
            }
            double xy[2] = {0.0, 0.0};
            for (std::size_t j = 0; j < 2; ++j) {
                const toml::node& x = (*e)[j];
                if (x.is_floating_point()) {
                    xy[j] = x.as_floating_point()->get();
                } else if (x.is_integer()) {
                    xy[j] = static_cast<double>(x.as_integer()->get());
                } else {
                    mcsim::fail(file_, ki, std::string("expected numbers (got ") + type_name(x) + ")");
                }
                if (!std::isfinite(xy[j])) {
                    mcsim::fail(file_, ki, "must be finite (got " + fmt_num(xy[j]) + ")");
                }
            }
            out.emplace_back(xy[0], xy[1]);
        }
        return out;
    }

private:
    const toml::table& t_;
    std::string file_;
    std::string prefix_;
};

// --- value checks: each names the key and shows the offending value -------
inline void gt(const View& v, const std::string& k, double x, double lo)
{
    if (!(x > lo)) {
        v.fail(k, "must be > " + fmt_num(lo) + " (got " + fmt_num(x) + ")");
    }
}
inline void ge(const View& v, const std::string& k, double x, double lo)
{
    if (!(x >= lo)) {
        v.fail(k, "must be >= " + fmt_num(lo) + " (got " + fmt_num(x) + ")");
    }
}
inline void le(const View& v, const std::string& k, double x, double hi)
{
    if (!(x <= hi)) {
        v.fail(k, "must be <= " + fmt_num(hi) + " (got " + fmt_num(x) + ")");
    }
}

// Largest scenario or motor file read (the shipped ones are 1-3 KB).
constexpr std::size_t kMaxFileBytes = 1u << 20;

// "U+03A9" for a valid UTF-8 sequence at s[i], else "byte 0xNN".

// profile_rpm of a speed drive's table: corners [[t_s, rpm], ...], the
// first at t = 0, at most SPEED_PROFILE_MAX_POINTS, times increasing by at
// least Ts_s (run.Ts_s is read first); into sc->speed_points [rad/s].
void read_speed_profile(const View& v, Scenario* sc);

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_TOML_VIEW_H

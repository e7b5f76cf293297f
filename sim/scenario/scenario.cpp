// scenario.cpp - TOML scenario parsing and validation (format: sim/scenarios/README.md).
#include "scenario/scenario.h"

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

#include <toml++/toml.h>

#include "model/switched_pwm.h"
#include "model/thermal.h"
#include "trajectory/speed_profile.h"
#include "scenario/toml_view.h"
#include "host_drives/host_drive.h"

namespace mcsim {
namespace {

namespace fs = std::filesystem;

std::string describe_non_ascii(const std::string& s, std::size_t i)
{
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    // sequence length from the lead byte (0: not a lead byte)
    const std::size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
    std::uint32_t cp = n == 4 ? c & 0x07u : n == 3 ? c & 0x0Fu : c & 0x1Fu;
    bool ok = n > 0 && i + n <= s.size();
    for (std::size_t k = 1; ok && k < n; ++k) {
        ok = (b(i + k) & 0xC0u) == 0x80u;
        cp = (cp << 6) | (b(i + k) & 0x3Fu);
    }
    ok = ok && !(n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) && !(n == 4 && (cp < 0x10000 || cp > 0x10FFFF));
    char buf[16];
    if (ok) {
        std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(cp));
    } else {
        std::snprintf(buf, sizeof buf, "byte 0x%02X", static_cast<unsigned>(c));
    }
    return buf;
}

// toml++ 3.3.0 (Debian 12) reaches __builtin_unreachable(), undefined
// behaviour, when it asks whether some non-ASCII characters are whitespace
// (most of U+00A1-U+0499, Greek letters included, and a few other ranges):
// a line "Φ_Wb = 0.01" or "x = 1 Ω" does it (found by tests/fuzz; reported
// upstream as marzer/tomlplusplus#190 and #295, fixed there by #305).
// TOML allows non-ASCII characters only in comments and strings, so one
// anywhere else (strings and comments as toml++ would find them) is
// refused here, before toml++ reads the file, as "FILE:LINE:COL: ..." like
// its syntax errors. In a multi-line basic string toml++ does the same
// lookup on the character after a backslash and on the first one after a
// line-ending backslash: a non-ASCII character there is refused too (valid
// TOML in the second case). Comments and strings may otherwise hold any
// UTF-8.
void check_non_ascii(const std::string& path, const std::string& s)
{
    enum class In { kCode, kComment, kBasic, kLiteral, kMlBasic, kMlLiteral } in = In::kCode;
    std::size_t line = 1, col = 0;  // col: code points (as toml++), of s[i]
    // Where toml++ would be in the code (outside strings and comments):
    std::string open;  // brackets open: 'h' table header, 'a' array, '{' inline table
    bool key = true;   // a key comes next (else a value)
    bool tok = false;  // inside a bare token: a key, or a value such as 1.5 or true
    // a line break: a key comes next, unless inside an array (its next value)
    const auto new_line = [&] {
        if (open.empty() || open.back() != 'a') {
            key = true;
        }
    };
    const auto at = [&](std::size_t k, char c) { return k < s.size() && s[k] == c; };
    const auto refuse = [&](std::size_t i, const std::string& where) {
        throw ScenarioError(path + ":" + std::to_string(line) + ":" + std::to_string(col) + ": non-ASCII character (" +
                            describe_non_ascii(s, i) + ") " + where);
    };
    std::size_t i = (s.compare(0, 3, "\xEF\xBB\xBF") == 0) ? 3 : 0;  // a UTF-8 byte order mark
    for (; i < s.size(); ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        if ((c & 0xC0u) != 0x80u) {
            ++col;
        }
        if (c == '\n') {
            ++line;
            col = 0;
        }
        switch (in) {
        case In::kCode: {
            if (c >= 0x80u) {
                refuse(i, "outside a string or a comment");
            }
            const bool blank = c == ' ' || c == '\t' || c == '\r' || c == '\n';
            if (tok && !key && !(blank || c == ',' || c == ']' || c == '}' || c == '#')) {
                // toml++ reads a bare value (a number, a date ...) up to
                // whitespace, ',', ']', '}' or '#' before it judges it: a
                // quote or bracket in there opens nothing (e.g. -'3 or +[")
                break;
            }
            tok = false;
            switch (c) {
            case '#':
                in = In::kComment;
                break;
            case '"':
            case '\'': {
                const bool ml = at(i + 1, static_cast<char>(c)) && at(i + 2, static_cast<char>(c));
                in = c == '"' ? (ml ? In::kMlBasic : In::kBasic) : (ml ? In::kMlLiteral : In::kLiteral);
                i += ml ? 2 : 0;
                col += ml ? 2 : 0;
                break;
            }
            case '\n':
                new_line();
                break;
            case '=':
                key = false;
                break;
            case '[':
                open += key ? 'h' : 'a';
                break;
            case '{':
                open += '{';
                key = true;
                break;
            case ',':
                key = !open.empty() && open.back() == '{';
                break;
            case ']':
            case '}':
                if (!open.empty()) {
                    open.pop_back();
                }
                key = false;
                break;
            case ' ':
            case '\t':
            case '\r':
            case '.':
                break;
            default:
                tok = true;
                break;
            }
            break;
        }
        case In::kComment:
            if (c == '\n') {
                in = In::kCode;
                new_line();
            }
            break;
        case In::kBasic:
        case In::kLiteral:
            if (c == '\n' || (in == In::kBasic && c == '"') || (in == In::kLiteral && c == '\'')) {
                in = In::kCode;  // (an unterminated string is toml++'s to report)
                if (c == '\n') {
                    new_line();
                }
            } else if (in == In::kBasic && c == '\\' && i + 1 < s.size() && s[i + 1] != '\n') {
                ++i;  // an escaped character (a non-ASCII one is toml++'s to report)
                col += (static_cast<unsigned char>(s[i]) & 0xC0u) != 0x80u ? 1 : 0;
            }
            break;
        case In::kMlBasic:
        case In::kMlLiteral: {
            const char q = in == In::kMlBasic ? '"' : '\'';
            if (c == static_cast<unsigned char>(q) && at(i + 1, q) && at(i + 2, q)) {
                // the closing quotes, and up to two more that belong to the string
                std::size_t n = 3;
                while (n < 5 && at(i + n, q)) {
                    ++n;
                }
                i += n - 1;
                col += n - 1;
                in = In::kCode;
            } else if (in == In::kMlBasic && c == '\\') {
                // toml++ asks whether the character after the backslash is
                // whitespace (a line-ending backslash may have blanks after
                // it); after blanks it wants a line break and skips all the
                // whitespace that follows: the first other character goes
                // through the same lookup.
                const auto ws = [&](std::size_t j) {
                    return j < s.size() && (s[j] == ' ' || s[j] == '\t' || (s[j] >= '\n' && s[j] <= '\r'));
                };
                const auto non_ascii = [&](std::size_t j) {
                    return j < s.size() && static_cast<unsigned char>(s[j]) >= 0x80u;
                };
                std::size_t k = i + 1;
                if (non_ascii(k)) {
                    ++col;
                    refuse(k, "right after a backslash in a multi-line string");
                }
                if (!ws(k)) {
                    if (k < s.size()) {
                        ++i;  // an escaped (ASCII) character
                        ++col;
                    }
                    break;
                }
                while (at(k, ' ') || at(k, '\t')) {
                    ++col;
                    ++k;
                }
                if (non_ascii(k)) {
                    ++col;
                    refuse(k, "after the blanks of a line-ending backslash");
                }
                while (ws(k)) {
                    if (s[k] == '\n') {
                        ++line;
                        col = 0;
                    } else {
                        ++col;
                    }
                    ++k;
                }
                if (non_ascii(k)) {
                    ++col;
                    refuse(k, "first after a line-ending backslash");
                }
                i = k - 1;
            }
            break;
        }
        }
    }
}

toml::table parse_toml(const std::string& path)
{
    std::string text;
    {
        std::ifstream f(path, std::ios::binary);
        if (!f) {
            throw ScenarioError(path + ": File could not be opened for reading");
        }
        char buf[16384];
        while (f.read(buf, sizeof buf) || f.gcount() > 0) {
            text.append(buf, static_cast<std::size_t>(f.gcount()));
            if (text.size() > kMaxFileBytes) {
                throw ScenarioError(path + ": larger than " + std::to_string(kMaxFileBytes) +
                                    " bytes: not a scenario or motor file");
            }
        }
        if (f.bad()) {
            throw ScenarioError(path + ": read error");
        }
    }
    check_non_ascii(path, text);
    try {
        return toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        std::string where = path;
        if (b.line > 0) {
            where += ":" + std::to_string(b.line) + ":" + std::to_string(b.column);
        }
        std::string d(e.description());
        std::replace(d.begin(), d.end(), '\n', ' ');
        throw ScenarioError(where + ": " + d);
    }
}

// Motor fields shared by motor files, [motor] overrides and [drive_model].
// `required` makes the core fields mandatory (motor files); `with_friction`
// admits the Coulomb keys, which only the plant has.
void read_motor_fields(const View& v, MotorParams* m, bool required, bool with_friction)
{
    auto num = [&](const char* k, double* dst) {
        const auto x = v.number(k);
        if (x) {
            *dst = *x;
        } else if (required) {
            v.fail(k, "missing required field");
        }
        return x.has_value();
    };
    const bool pmsm = m->type == MotorType::kPmsm3;
    // keys of the other motor type are errors, not silently ignored
    const std::vector<std::string> stepper_only = {"L_H", "K_Nm_per_A"};
    const std::vector<std::string> pmsm_only = {"L_d_H", "L_q_H", "Phi_Wb"};
    for (const std::string& k : pmsm ? stepper_only : pmsm_only) {
        if (v.has(k)) {
            v.fail(k, pmsm ? "only for type = \"stepper2\" (this motor is \"pmsm3\": use L_d_H, L_q_H, Phi_Wb)"
                           : "only for type = \"pmsm3\" (this motor is \"stepper2\": use L_H, K_Nm_per_A)");
        }
    }
    double phi = (m->n_p > 0) ? m->K_Nm_per_A / static_cast<double>(m->n_p) : 0.0;
    const auto np = v.integer("n_p");
    if (np) {
        if (*np < 1 || *np > 10000) {
            v.fail("n_p", "must be an integer in [1, 10000] (got " + std::to_string(*np) + ")");
        }
        m->n_p = static_cast<int>(*np);
    } else if (required) {
        v.fail("n_p", "missing required field");
    }
    if (pmsm) {
        if (num("L_d_H", &m->L_H)) gt(v, "L_d_H", m->L_H, 0.0);
        if (num("L_q_H", &m->L_q_H)) gt(v, "L_q_H", m->L_q_H, 0.0);
        if (num("Phi_Wb", &phi)) gt(v, "Phi_Wb", phi, 0.0);
        m->K_Nm_per_A = static_cast<double>(m->n_p) * phi;  // K_e = n_p Phi
    } else {
        if (num("L_H", &m->L_H)) gt(v, "L_H", m->L_H, 0.0);
        if (num("K_Nm_per_A", &m->K_Nm_per_A)) gt(v, "K_Nm_per_A", m->K_Nm_per_A, 0.0);
    }
    if (num("R_ohm", &m->R_ohm)) ge(v, "R_ohm", m->R_ohm, 0.0);
    if (num("J_kgm2", &m->J_kgm2)) gt(v, "J_kgm2", m->J_kgm2, 0.0);
    if (num("fv_Nms_per_rad", &m->fv_Nms_per_rad)) ge(v, "fv_Nms_per_rad", m->fv_Nms_per_rad, 0.0);
    if (with_friction) {
        const auto c = v.number("coulomb_Nm");
        if (c) {
            ge(v, "coulomb_Nm", *c, 0.0);
            m->coulomb_Nm = *c;
        }
        // LuGre (paper 002 (45)-(46)): all six or none
        const char* lugre_keys[6] = {"lugre_sigma0_Nm_per_rad", "lugre_sigma1_Nms_per_rad", "lugre_sigma2_Nms_per_rad",
                                     "lugre_Mc_Nm", "lugre_Ms_Nm", "lugre_ws_rad_s"};
        double* lugre_dst[6] = {&m->lugre_sigma0_Nm_per_rad, &m->lugre_sigma1_Nms_per_rad, &m->lugre_sigma2_Nms_per_rad,
                                &m->lugre_Mc_Nm, &m->lugre_Ms_Nm, &m->lugre_ws_rad_s};
        int n_lugre = 0;
        for (int i = 0; i < 6; ++i) {
            if (const auto x = v.number(lugre_keys[i])) {
                ge(v, lugre_keys[i], *x, 0.0);
                *lugre_dst[i] = *x;
                ++n_lugre;
            }
        }
        if (n_lugre != 0 && n_lugre != 6) {
            v.fail(lugre_keys[0], "LuGre friction needs all six lugre_* keys (sigma0, sigma1, sigma2, Mc, Ms, ws)");
        }
        if (n_lugre == 6) {
            gt(v, "lugre_sigma0_Nm_per_rad", m->lugre_sigma0_Nm_per_rad, 0.0);
            gt(v, "lugre_Mc_Nm", m->lugre_Mc_Nm, 0.0);
            gt(v, "lugre_ws_rad_s", m->lugre_ws_rad_s, 0.0);
            if (m->lugre_Ms_Nm < m->lugre_Mc_Nm) v.fail("lugre_Ms_Nm", "the stiction level must be >= lugre_Mc_Nm");
        }
        const auto ws = v.number("coulomb_omega_s_rad_s");
        if (ws) {
            gt(v, "coulomb_omega_s_rad_s", *ws, 0.0);
            m->coulomb_omega_s_rad_s = *ws;
        }
        // the plant's saturation and temperature (issue 30; docs/plant.md):
        // the plant's only, like the friction
        const auto opt = [&](const char* k, double* dst) {
            if (const auto x = v.number(k)) {
                *dst = *x;
                return true;
            }
            return false;
        };
        if (opt("i_sat_A", &m->i_sat_A)) ge(v, "i_sat_A", m->i_sat_A, 0.0);
        if (opt("i_sat_bias_A", &m->i_sat_bias_A)) {
            ge(v, "i_sat_bias_A", m->i_sat_bias_A, 0.0);
            if (m->i_sat_bias_A > 0.0 && !(m->i_sat_A > 0.0)) {
                v.fail("i_sat_bias_A", "the magnet's bias on the iron needs its saturation: i_sat_A > 0");
            }
        }
        if (opt("R_th_K_per_W", &m->R_th_K_per_W)) ge(v, "R_th_K_per_W", m->R_th_K_per_W, 0.0);
        if (opt("C_th_J_per_K", &m->C_th_J_per_K)) ge(v, "C_th_J_per_K", m->C_th_J_per_K, 0.0);
        if ((m->R_th_K_per_W > 0.0) != (m->C_th_J_per_K > 0.0)) {
            v.fail(m->R_th_K_per_W > 0.0 ? "C_th_J_per_K" : "R_th_K_per_W",
                   "R_th_K_per_W and C_th_J_per_K go together (both > 0, or both 0 for no thermal model)");
        }
        if (opt("T_ambient_C", &m->T_ambient_C)) ge(v, "T_ambient_C", m->T_ambient_C, ThermalModel::kAbsoluteZero_C);
        if (opt("T0_C", &m->T0_C)) ge(v, "T0_C", m->T0_C, ThermalModel::kAbsoluteZero_C);
        opt("alpha_cu_per_K", &m->alpha_cu_per_K);
        opt("beta_pm_per_K", &m->beta_pm_per_K);
        // R(T0) and Phi(T0) must stay positive (T2), (T3)
        if (!(1.0 + m->alpha_cu_per_K * (m->T0_C - ThermalModel::kTref_C) > 0.0)) {
            v.fail(v.has("alpha_cu_per_K") ? "alpha_cu_per_K" : "T0_C",
                   "R_ohm (1 + alpha_cu_per_K (T0_C - 20)) must be > 0");
        }
        if (!(1.0 + m->beta_pm_per_K * (m->T0_C - ThermalModel::kTref_C) > 0.0)) {
            v.fail(v.has("beta_pm_per_K") ? "beta_pm_per_K" : "T0_C",
                   "the flux (1 + beta_pm_per_K (T0_C - 20)) must be > 0");
        }
    }
}

// A function-local static: built on first use, not during static
// initialisation, where an exception could not be caught.
const std::vector<std::string>& motor_file_keys()
{
    static const std::vector<std::string> k = {"name",   "source",         "description", "type",
                                               "L_H",    "K_Nm_per_A",     "L_d_H",       "L_q_H",
                                               "Phi_Wb", "R_ohm",          "J_kgm2",      "fv_Nms_per_rad",
                                               "coulomb_Nm", "coulomb_omega_s_rad_s", "n_p",
                                               "lugre_sigma0_Nm_per_rad", "lugre_sigma1_Nms_per_rad",
                                               "lugre_sigma2_Nms_per_rad", "lugre_Mc_Nm", "lugre_Ms_Nm",
                                               "lugre_ws_rad_s", "i_sat_A", "i_sat_bias_A", "R_th_K_per_W", "C_th_J_per_K",
                                               "T_ambient_C", "T0_C", "alpha_cu_per_K", "beta_pm_per_K"};
    return k;
}

MotorParams read_motor_file(const std::string& path)
{
    const toml::table t = parse_toml(path);
    const View v(t, path, "");
    v.only(motor_file_keys());
    v.string("name");
    v.string("source");
    v.string("description");
    MotorParams m;
    const auto type = v.string("type");
    if (!type) {
        v.fail("type", "missing required field (\"stepper2\" or \"pmsm3\")");
    }
    if (*type == "stepper2") {
        m.type = MotorType::kStepper2;
    } else if (*type == "pmsm3") {
        m.type = MotorType::kPmsm3;
    } else {
        v.fail("type", "must be \"stepper2\" or \"pmsm3\" (got \"" + *type + "\")");
    }
    read_motor_fields(v, &m, true, true);
    return m;
}

}  // namespace

std::uint32_t Scenario::n_ticks() const
{
    return static_cast<std::uint32_t>(std::llround(duration_s / ts_s)) + pre_ticks;
}

MotorParams load_motor_file(const std::string& path) { return read_motor_file(path); }

// [board]: the DAC/ADC board of motorsim --backend board-emulated (and of
// the Comedi backend). Every key has a default: a DS1104-like card (8 A/D
// and 8 D/A channels, 16 bits, +-10 V), the amplifier's gain that puts the
// D/A range on the supply, a Hall sensor gain that puts 1.25 i_trip on the
// A/D range, the bus through a divider that puts 1.25 times it there, and
// as the emulated hardware's imperfections: offsets of 2 % of full scale,
// gain errors of 1 % (Hall sensors), 1 mV of noise (3 codes).
void read_board(const View* v, Scenario* sc)
{
    BoardParams& b = sc->board;
    board_chain_config_t& c = b.chain;
    const int n_ph = sc->motor.n_phases();
    const double v_phase = sc->v_max_V;                     // a phase's largest voltage
    const double v_bus = n_ph == 3 ? 2.0 * v_phase : v_phase; // the bus (hal_sw_plant.h)
    c.n_phases = n_ph;
    c.ai_channels = 8;
    c.ao_channels = 8;
    for (int k = 0; k < 3; ++k) {
        c.current_ai[k] = k;
        c.voltage_ao[k] = k;
    }
    c.vbus_ai = n_ph;
    c.adc_bits = 16;
    c.dac_bits = 16;
    c.adc_range_V = 10.0;
    c.dac_range_V = 10.0;
    c.supply_V = v_phase;
    c.offset_max_V = 0.5;
    b.calibration_samples = 1000;
    const double offsets[3] = {0.2, -0.15, 0.1};
    const double gains[3] = {0.01, -0.01, 0.005};
    for (int k = 0; k < 3; ++k) {
        b.sensor_offset_V[k] = offsets[k];
        b.sensor_gain_error[k] = gains[k];
    }
    b.noise_V = 1e-3;
    if (v != nullptr) {
        v->only({"ai_channels", "ao_channels", "current_channels", "vbus_channel", "voltage_channels", "adc_bits",
                 "dac_bits", "adc_range_V", "dac_range_V", "sensor_V_per_A", "amplifier_V_per_V", "vbus_V_per_V",
                 "offset_max_V", "calibration_samples", "sensor_offset_V", "sensor_gain_error", "noise_V"});
        sc->board_given = true;
        auto int_of = [&](const char* k, int* out) {
            if (const auto x = v->integer(k)) {
                if (*x < -1000000 || *x > 1000000) v->fail(k, "out of range");
                *out = static_cast<int>(*x);
            }
        };
        auto num_of = [&](const char* k, double* out) {
            if (const auto x = v->number(k)) *out = *x;
        };
        auto ints_of = [&](const char* k, int* out) {
            const toml::node* n = v->raw().get(k);
            if (n == nullptr) return;
            const toml::array* a = n->as_array();
            if (a == nullptr || static_cast<int>(a->size()) != n_ph) {
                v->fail(k, "expected an array of " + std::to_string(n_ph) + " channel numbers, one per phase");
            }
            for (int i = 0; i < n_ph; ++i) {
                const toml::node& e = (*a)[static_cast<std::size_t>(i)];
                if (!e.is_integer()) v->fail(k, "expected integers (channel numbers)");
                out[i] = static_cast<int>(e.as_integer()->get());
            }
        };
        auto nums_of = [&](const char* k, double* out) {
            const toml::node* n = v->raw().get(k);
            if (n == nullptr) return;
            const toml::array* a = n->as_array();
            if (a == nullptr || static_cast<int>(a->size()) != n_ph) {
                v->fail(k, "expected an array of " + std::to_string(n_ph) + " numbers, one per phase");
            }
            for (int i = 0; i < n_ph; ++i) {
                const toml::node& e = (*a)[static_cast<std::size_t>(i)];
                if (!e.is_number()) v->fail(k, "expected numbers");
                out[i] = e.is_floating_point() ? e.as_floating_point()->get() : static_cast<double>(e.as_integer()->get());
                if (!std::isfinite(out[i])) v->fail(k, "must be finite");
            }
        };
        int_of("ai_channels", &c.ai_channels);
        int_of("ao_channels", &c.ao_channels);
        ints_of("current_channels", c.current_ai);
        int_of("vbus_channel", &c.vbus_ai);
        ints_of("voltage_channels", c.voltage_ao);
        int_of("adc_bits", &c.adc_bits);
        int_of("dac_bits", &c.dac_bits);
        num_of("adc_range_V", &c.adc_range_V);
        num_of("dac_range_V", &c.dac_range_V);
        num_of("offset_max_V", &c.offset_max_V);
        int_of("calibration_samples", &b.calibration_samples);
        nums_of("sensor_offset_V", b.sensor_offset_V);
        nums_of("sensor_gain_error", b.sensor_gain_error);
        num_of("noise_V", &b.noise_V);
        if (b.calibration_samples < 1) v->fail("calibration_samples", "must be >= 1");
        if (!(b.noise_V >= 0.0)) v->fail("noise_V", "must be >= 0");
        for (int k = 0; k < n_ph; ++k) {
            if (!(b.sensor_gain_error[k] > -1.0)) v->fail("sensor_gain_error", "must be > -1 (a gain of 0 or below)");
        }
    }
    // the derived gains, unless given
    c.amplifier_V_per_V = c.dac_range_V > 0.0 ? v_phase / c.dac_range_V : 0.0;
    c.sensor_V_per_A = sc->i_trip_A > 0.0 ? c.adc_range_V / (1.25 * sc->i_trip_A) : 0.0;
    c.vbus_V_per_V = c.adc_range_V > 0.0 ? 1.25 * v_bus / c.adc_range_V : 0.0;
    if (v != nullptr) {
        if (const auto x = v->number("sensor_V_per_A")) c.sensor_V_per_A = *x;
        if (const auto x = v->number("amplifier_V_per_V")) c.amplifier_V_per_V = *x;
        if (const auto x = v->number("vbus_V_per_V")) c.vbus_V_per_V = *x;
    }
    char err[240];
    if (!board_chain_check(&c, err, sizeof err)) {
        throw ScenarioError(sc->path + ": " + err);
    }
    // the bus is 2 v_max with three legs (board_chain_check looked at v_max)
    if (c.vbus_ai >= 0 && c.adc_range_V * c.vbus_V_per_V < v_bus) {
        throw ScenarioError(sc->path + ": board.vbus_V_per_V: the A/D range through the divider holds " +
                            fmt_num(c.adc_range_V * c.vbus_V_per_V) + " V, less than the " + fmt_num(v_bus) +
                            " V bus");
    }
}

// The keys of each table the parser reads itself (each table's `only`
// list; a drive's table is its host part's, sim/host_drives/), in one
// place: motorsim --scenario-keys prints them with the drives' and the
// motor file's, and ctest docs.scenario_keys checks sim/scenarios/README.md
// against them both ways.
const std::vector<std::pair<std::string, std::vector<std::string>>>& parser_tables()
{
    static const std::vector<std::pair<std::string, std::vector<std::string>>> k = {
        {"run", {"duration_s", "Ts_s", "seed", "substeps", "theta0_rad", "compute_delay_samples"}},
        {"drive_model", {"L_H", "R_ohm", "K_Nm_per_A", "L_d_H", "L_q_H", "Phi_Wb", "J_kgm2", "fv_Nms_per_rad", "n_p"}},
        {"supply", {"v_max_V", "v_bus_V"}},
        {"limits", {"i_max_A", "i_trip_A", "i_trip_samples", "omega_lim_rad_s", "i_open_loop_A"}},
        {"sensor", {"noise", "noise_A", "adc_bits", "adc_full_scale_A"}},
        {"faults", {"locked_rotor_t_s", "open_phase", "sensor_offset", "sensor_gain", "noise_burst", "stuck_samples", "nan_sample_t_s", "supply_sag", "overruns"}},
        {"load", {"steps", "pulses"}},
        {"encoder", {"counts_per_turn", "noise_rad"}},
        {"inverter", {"file", "compensation", "compensation_dead_time_s", "f_pwm_Hz", "dead_time_s", "t_on_s", "t_off_s", "v_switch_V",
                      "r_switch_Ohm", "v_diode_V", "r_diode_Ohm", "min_pulse_s", "i_transition_A", "synchronous", "pwm"}},
        {"drive", {"kind"}}};
    return k;
}

const std::vector<std::string>& table_keys(const std::string& table)
{
    for (const auto& kv : parser_tables()) {
        if (kv.first == table) {
            return kv.second;
        }
    }
    throw std::logic_error("scenario.cpp: no key list for [" + table + "]");
}

std::vector<std::string> top_level_keys()
{
    std::vector<std::string> top = {"description", "run", "motor", "drive_model", "supply", "limits", "sensor", "load",
                                    "expect", "faults", "board", "encoder", "drive", "inverter"};
    const auto add = [&top](const std::string& table) {
        if (table.find('.') == std::string::npos && std::find(top.begin(), top.end(), table) == top.end()) {
            top.push_back(table);
        }
    };
    for (const HostDrive* d : host_drives()) {
        add(d->table);  // each registered drive's own table, and its further ones
        if (d->extra_keys != nullptr) {
            for (const auto& kv : d->extra_keys()) {
                add(kv.first);
            }
        }
    }
    return top;
}

std::vector<std::pair<std::string, std::vector<std::string>>> scenario_keys()
{
    std::vector<std::pair<std::string, std::vector<std::string>>> k = parser_tables();
    k.emplace_back("top", top_level_keys());
    k.emplace_back("motor_file", motor_file_keys());
    for (const HostDrive* d : host_drives()) {
        k.emplace_back(d->table, d->keys());
        if (d->extra_keys != nullptr) {
            for (auto& kv : d->extra_keys()) {
                k.push_back(std::move(kv));
            }
        }
    }
    return k;
}

void read_speed_profile(const View& v, Scenario* sc)
{
    const auto pts = v.pairs("profile_rpm");
    if (!pts || pts->empty()) {
        v.fail("profile_rpm", "missing required field (corners [[t_s, rpm], ...], the first at t = 0)");
    }
    if (pts->size() > static_cast<std::size_t>(SPEED_PROFILE_MAX_POINTS)) {
        v.fail("profile_rpm", "at most " + std::to_string(SPEED_PROFILE_MAX_POINTS) + " corners (got " +
                                  std::to_string(pts->size()) + ")");
    }
    for (std::size_t i = 0; i < pts->size(); ++i) {
        const double t = (*pts)[i].first;
        if (i == 0 && t != 0.0) {
            v.fail("profile_rpm", "the first corner must be at t = 0 (got " + fmt_num(t) + ")");
        }
        if (i > 0 && !(t - (*pts)[i - 1].first >= sc->ts_s)) {
            v.fail("profile_rpm", "corner times must increase by at least Ts_s (corner " + std::to_string(i) +
                                      " at " + fmt_num(t) + " s)");
        }
        sc->speed_points.emplace_back(t, (*pts)[i].second * kRpmToRadS);
    }
}

namespace {

// --- one parser per table: each reads its table (nullptr: absent) into
// *sc, after the tables before it in kSections (their values are there).

// [run] (required)
void read_run(const View* t, Scenario* sc)
{
    const View& v = *t;
    v.only(table_keys("run"));
    sc->duration_s = v.number_req("duration_s");
    gt(v, "duration_s", sc->duration_s, 0.0);
    sc->ts_s = v.number_req("Ts_s");
    gt(v, "Ts_s", sc->ts_s, 0.0);
    le(v, "Ts_s", sc->ts_s, sc->duration_s);
    // hal_time_us() and the firmware's tick counter are 32-bit.
    if (sc->duration_s / sc->ts_s > 4.0e9) {
        v.fail("duration_s", "more than 4e9 samples of Ts_s (got " + fmt_num(sc->duration_s / sc->ts_s) + ")");
    }
    if (const auto s = v.integer("seed")) {
        if (*s < 0) {
            v.fail("seed", "must be >= 0 (got " + std::to_string(*s) + ")");
        }
        sc->seed = static_cast<std::uint64_t>(*s);
    }
    if (const auto n = v.integer("substeps")) {
        if (*n < 1 || *n > kMaxSubsteps) {
            v.fail("substeps", "must be an integer in [1, " + std::to_string(kMaxSubsteps) + "] (got " +
                                   std::to_string(*n) + ")");
        }
        sc->substeps = static_cast<int>(*n);
        sc->substeps_given = true;
    }
    sc->theta0_rad = v.number("theta0_rad").value_or(0.0);
    if (const auto d = v.number("compute_delay_samples")) {
        if (!(*d >= 0.0 && *d <= 1.0)) {
            v.fail("compute_delay_samples", "must be in [0, 1] (got " + fmt_num(*d) + ")");
        }
        sc->compute_delay_samples = *d;
    }
}

// The plant's integration step against the motor's fastest modes: RK4 is
// stable for h lambda < 2.78 on the real axis and 2.83 on the imaginary
// one, and accurate well inside; h lambda <= 1 is asked here. Modes: the
// electrical R/L (R/L_q too), the Coulomb friction's tanh slope
// C/(w_s J), viscous f_v/J, and the electromechanical oscillation
// sqrt(K_e K_t/(L J)). Without [run] substeps the sub-steps are chosen;
// with it, too few is an error naming the keys.
void choose_substeps(Scenario* sc)
{
    const MotorParams& m = sc->motor;
    const double L_min = std::min(m.L_H, m.L_q());
    const double K = m.K_Nm_per_A;
    struct Mode {
        double rate;
        const char* keys;
    } modes[] = {{m.R_ohm / L_min, "motor R_ohm / L (L_H or L_d_H, L_q_H)"},
                 {m.coulomb_Nm / (m.coulomb_omega_s_rad_s * m.J_kgm2), "motor coulomb_Nm / (coulomb_omega_s_rad_s J_kgm2)"},
                 {m.fv_Nms_per_rad / m.J_kgm2, "motor fv_Nms_per_rad / J_kgm2"},
                 {std::sqrt(K * K * m.torque_scale() / (L_min * m.J_kgm2)), "motor K (Phi_Wb n_p) / sqrt(L J_kgm2)"}};
    const Mode* fastest = &modes[0];
    for (const Mode& md : modes) {
        if (std::isfinite(md.rate) && md.rate > fastest->rate) {
            fastest = &md;
        }
    }
    const double need = std::ceil(sc->ts_s * fastest->rate / kRk4StepTimesRateMax);
    if (need > static_cast<double>(sc->substeps)) {
        const std::string why = "the plant's fastest mode (" + std::string(fastest->keys) + " = " +
                                fmt_num(fastest->rate) + " 1/s) needs " + fmt_num(need) +
                                " RK4 sub-steps per Ts_s = " + fmt_num(sc->ts_s) + " s";
        if (need > static_cast<double>(kMaxSubsteps)) {
            fail(sc->path, "motor", why + ", more than the " + std::to_string(kMaxSubsteps) +
                                        " allowed: the motor file's values are implausible for this Ts_s");
        }
        if (sc->substeps_given) {
            fail(sc->path, "run.substeps", why + " (got " + std::to_string(sc->substeps) + ")");
        }
        sc->substeps = static_cast<int>(need);
    }
}

// [motor] (required): a motor file plus optional overrides; then the
// plant's RK4 sub-steps for it
void read_motor(const View* t, Scenario* sc)
{
    const View& v = *t;
    std::vector<std::string> allowed = motor_file_keys();
    allowed.erase(allowed.begin(), allowed.begin() + 4);  // no name/source/description/type here
    allowed.push_back("file");
    v.only(allowed);
    const auto file = v.string("file");
    if (!file) {
        v.fail("file", "missing required field");
    }
    // Relative to the scenario file, so scenarios work from any cwd.
    fs::path mp(*file);
    if (mp.is_relative()) {
        mp = fs::path(sc->path).parent_path() / mp;
    }
    sc->motor_file = mp.lexically_normal().string();
    std::error_code ec;
    if (!fs::is_regular_file(sc->motor_file, ec)) {
        v.fail("file", "cannot open motor file '" + sc->motor_file + "'");
    }
    sc->motor = read_motor_file(sc->motor_file);
    read_motor_fields(v, &sc->motor, false, true);
    choose_substeps(sc);
}

// [drive_model]: what the drive is designed for; defaults to the plant.
void read_drive_model(const View* v, Scenario* sc)
{
    sc->drive_model = sc->motor;
    if (v != nullptr) {
        v->only(table_keys("drive_model"));
        read_motor_fields(*v, &sc->drive_model, false, false);
    }
}

// [supply] (required)
void read_supply(const View* t, Scenario* sc)
{
    const View& v = *t;
    v.only(table_keys("supply"));
    if (sc->motor.type == MotorType::kPmsm3) {
        // three legs on one bus: each swings +-v_bus/2 about the midpoint
        if (v.has("v_max_V")) {
            v.fail("v_max_V", "only for a stepper2 motor (a pmsm3 motor takes v_bus_V)");
        }
        const double vb = v.number_req("v_bus_V");
        gt(v, "v_bus_V", vb, 0.0);
        sc->v_max_V = 0.5 * vb;
    } else {
        if (v.has("v_bus_V")) {
            if (v.has("v_max_V")) {
                v.fail("v_bus_V", "give v_max_V or v_bus_V, not both (equal for H-bridges)");
            }
            sc->v_max_V = v.number_req("v_bus_V");
            gt(v, "v_bus_V", sc->v_max_V, 0.0);
        } else {
            sc->v_max_V = v.number_req("v_max_V");
            gt(v, "v_max_V", sc->v_max_V, 0.0);
        }
    }
}

// [limits] (required)
void read_limits(const View* t, Scenario* sc)
{
    const View& v = *t;
    v.only(table_keys("limits"));
    sc->i_max_A = v.number_req("i_max_A");
    gt(v, "i_max_A", sc->i_max_A, 0.0);
    sc->i_trip_A = v.number("i_trip_A").value_or(1.5 * sc->i_max_A);
    if (v.has("i_trip_A")) {
        ge(v, "i_trip_A", sc->i_trip_A, sc->i_max_A);
    }
    if (const auto n = v.integer("i_trip_samples")) {
        if (*n < 1 || *n > 8) {
            v.fail("i_trip_samples", "must be 1..8 (got " + std::to_string(*n) + ")");
        }
        sc->i_trip_samples = static_cast<int>(*n);
    }
    if (const auto w = v.number("omega_lim_rad_s")) {  // a drive's part may require it (paper000_host.cpp)
        gt(v, "omega_lim_rad_s", *w, 0.0);
        sc->omega_lim_rad_s = *w;
    }
    if (const auto i = v.number("i_open_loop_A")) {
        gt(v, "i_open_loop_A", *i, 0.0);
        le(v, "i_open_loop_A", *i, sc->i_max_A);
        sc->i_open_loop_A = *i;
    }
}

// [sensor] (optional: an ideal sensor)
void read_sensor(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    v->only(table_keys("sensor"));
    const std::string kind = v->string("noise").value_or("none");
    if (kind == "none") {
        sc->sensor.noise = NoiseKind::kNone;
    } else if (kind == "uniform") {
        sc->sensor.noise = NoiseKind::kUniform;
    } else if (kind == "gaussian") {
        sc->sensor.noise = NoiseKind::kGaussian;
    } else {
        v->fail("noise", "must be \"none\", \"uniform\" or \"gaussian\" (got \"" + kind + "\")");
    }
    const auto n = v->number("noise_A");
    if (n) {
        ge(*v, "noise_A", *n, 0.0);
        sc->sensor.noise_A = *n;
    } else if (sc->sensor.noise != NoiseKind::kNone) {
        v->fail("noise_A", "missing required field (noise is \"" + kind + "\")");
    }
    if (const auto b = v->integer("adc_bits")) {
        if (*b < 0 || *b > 32) {
            v->fail("adc_bits", "must be an integer in [0, 32] (got " + std::to_string(*b) + ")");
        }
        sc->sensor.adc_bits = static_cast<int>(*b);
    }
    const auto fsA = v->number("adc_full_scale_A");
    if (fsA) {
        gt(*v, "adc_full_scale_A", *fsA, 0.0);
        sc->sensor.adc_full_scale_A = *fsA;
    } else if (sc->sensor.adc_bits > 0) {
        v->fail("adc_full_scale_A", "missing required field (adc_bits > 0)");
    }
}

// [faults] (optional): injected faults (model/fault_injection.h)
void read_faults(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    v->only(table_keys("faults"));
    FaultInjection& f = sc->faults;
    const int n_ph = sc->motor.n_phases();
    auto time_of = [](const View& t, const char* k) {
        const double x = t.number_req(k);
        ge(t, k, x, 0.0);
        return x;
    };
    auto phase_of = [&](const View& t) {
        const std::string ph = t.string("phase").value_or("");
        const int k = ph == "a" ? 0 : ph == "b" ? 1 : ph == "c" ? 2 : -1;
        if (k < 0 || k >= n_ph) {
            t.fail("phase", "must be one of the motor's phases " + std::string(n_ph == 3 ? "\"a\", \"b\", \"c\"" : "\"a\", \"b\"") +
                                " (got \"" + ph + "\")");
        }
        return k;
    };
    // an array of one number per phase
    auto per_phase = [&](const View& t, const char* k, double* out) {
        const auto x = t.numbers(k, static_cast<std::size_t>(n_ph), [](double) { return true; }, "must be finite");
        if (!x) {
            t.fail(k, "missing required field: an array of " + std::to_string(n_ph) + " numbers, one per phase");
        }
        std::copy(x->begin(), x->end(), out);
    };
    if (v->has("locked_rotor_t_s")) {
        f.locked_rotor_t_s = time_of(*v, "locked_rotor_t_s");
    }
    if (const auto t = v->table("open_phase")) {
        t->only({"t_s", "phase"});
        if (n_ph != 2) {
            v->fail("open_phase", "only for two-phase motors (type = \"stepper2\"): an open phase of a star-connected motor is not modelled");
        }
        f.open_phase_t_s = time_of(*t, "t_s");
        f.open_phase = phase_of(*t);
    }
    if (const auto t = v->table("sensor_offset")) {
        t->only({"t_s", "offset_A"});
        f.offset_t_s = time_of(*t, "t_s");
        per_phase(*t, "offset_A", f.offset_A);
    }
    if (const auto t = v->table("sensor_gain")) {
        t->only({"t_s", "gain"});
        f.gain_t_s = time_of(*t, "t_s");
        per_phase(*t, "gain", f.gain);
    }
    if (const auto t = v->table("noise_burst")) {
        t->only({"t_s", "duration_s", "noise_A"});
        f.burst_t_s = time_of(*t, "t_s");
        f.burst_duration_s = t->number_req("duration_s");
        gt(*t, "duration_s", f.burst_duration_s, 0.0);
        f.burst_noise_A = t->number_req("noise_A");
        gt(*t, "noise_A", f.burst_noise_A, 0.0);
    }
    if (const auto t = v->table("stuck_samples")) {
        t->only({"t_s", "phase"});
        f.stuck_t_s = time_of(*t, "t_s");
        f.stuck_phase = phase_of(*t);
    }
    if (v->has("nan_sample_t_s")) {
        f.nan_t_s = time_of(*v, "nan_sample_t_s");
    }
    if (const auto t = v->table("supply_sag")) {
        t->only({"t_s", "duration_s", "v_max_V"});
        f.sag_t_s = time_of(*t, "t_s");
        f.sag_duration_s = t->number_req("duration_s");
        gt(*t, "duration_s", f.sag_duration_s, 0.0);
        f.sag_v_max_V = t->number_req("v_max_V");
        ge(*t, "v_max_V", f.sag_v_max_V, 0.0);
        le(*t, "v_max_V", f.sag_v_max_V, sc->v_max_V);
    }
    if (const auto t = v->table("overruns")) {
        t->only({"t_s", "count"});
        f.overrun_t_s = time_of(*t, "t_s");
        const auto c = t->integer("count");
        if (!c || *c < 1 || *c > 1000000) {
            t->fail("count", "must be an integer in [1, 1000000]");
        }
        f.overrun_count = static_cast<int>(*c);
    }
}

// [load] (optional: no external load): steps, or a pulse train
void read_load(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    v->only(table_keys("load"));
    if (v->has("steps") && v->has("pulses")) {
        v->fail("pulses", "give either steps or pulses, not both");
    }
    auto edge_of = [](const View& t) {
        const std::string e = t.string("edge").value_or("linear");
        if (e != "linear" && e != "raised_cosine") {
            t.fail("edge", "must be \"linear\" or \"raised_cosine\" (got \"" + e + "\")");
        }
        return e == "raised_cosine";
    };
    if (const auto steps = v->tables("steps")) {
        double t_free = 0.0;  // earliest start of the next step
        for (const View& s : *steps) {
            s.only({"t_s", "torque_Nm", "ramp_s", "edge"});
            LoadStep ls;
            ls.t_s = s.number_req("t_s");
            ge(s, "t_s", ls.t_s, t_free);
            ls.torque_Nm = s.number_req("torque_Nm");
            ls.ramp_s = s.number("ramp_s").value_or(0.0);
            ge(s, "ramp_s", ls.ramp_s, 0.0);
            ls.raised_cosine = edge_of(s);
            t_free = ls.t_s + ls.ramp_s;
            sc->load.push_back(ls);
        }
    }
    // a pulse train (paper 002's load): torque_Nm from start_s every
    // period_s for width_s (the edges inside it), until the run's end
    if (const auto p = v->table("pulses")) {
        p->only({"torque_Nm", "start_s", "width_s", "period_s", "edge_s", "edge"});
        const double M = p->number_req("torque_Nm");
        const double t0 = p->number_req("start_s");
        const double w = p->number_req("width_s");
        const double T = p->number_req("period_s");
        const double e = p->number("edge_s").value_or(0.0);
        ge(*p, "start_s", t0, 0.0);
        gt(*p, "width_s", w, 0.0);
        gt(*p, "period_s", T, 0.0);
        ge(*p, "edge_s", e, 0.0);
        if (!(2.0 * e <= w)) p->fail("edge_s", "two edges must fit in width_s (got " + fmt_num(e) + " s)");
        if (!(w < T)) p->fail("width_s", "must be shorter than period_s");
        const bool cosine = edge_of(*p);
        if ((sc->duration_s - t0) / T > 10000.0) p->fail("period_s", "more than 10000 pulses in the run");
        const auto n_pulses = static_cast<int>(std::ceil((sc->duration_s - t0) / T));
        for (int k = 0; k < n_pulses; ++k) {
            const double t = t0 + static_cast<double>(k) * T;
            sc->load.push_back(LoadStep{t, M, e, cosine});
            sc->load.push_back(LoadStep{t + w - e, 0.0, e, cosine});
        }
    }
}

// [expect]: bounds on the run's metrics; names are checked against the
// drive's metrics before the run (motorsim), values here
void read_expect(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    for (const std::string& k : v->keys()) {
        const auto e = v->table(k);
        if (!e) {
            continue;
        }
        e->only({"max", "min"});
        Expectation x;
        x.metric = k;
        if (const auto hi = e->number("max")) {
            x.has_max = true;
            x.max = *hi;
        }
        if (const auto lo = e->number("min")) {
            x.has_min = true;
            x.min = *lo;
        }
        if (!x.has_max && !x.has_min) {
            v->fail(k, "needs max and/or min (e.g. { max = 0.03 })");
        }
        if (x.has_max && x.has_min && !(x.min <= x.max)) {
            v->fail(k, "min must be <= max (got min " + fmt_num(x.min) + ", max " + fmt_num(x.max) + ")");
        }
        sc->expect.push_back(x);
    }
}

// [encoder] (optional): the HAL's position input
void read_encoder(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    v->only(table_keys("encoder"));
    const auto n = v->integer("counts_per_turn");
    if (!n) v->fail("counts_per_turn", "missing required field");
    if (*n < 1 || *n > (std::int64_t{1} << 32)) {
        v->fail("counts_per_turn", "must be an integer in [1, 2^32] (got " + std::to_string(*n) + ")");
    }
    sc->encoder.counts_per_turn = *n;
    sc->encoder.noise_rad = v->number("noise_rad").value_or(0.0);
    ge(*v, "noise_rad", sc->encoder.noise_rad, 0.0);
}

// The inverter's parameters of a table or an inverter file
// (sim/inverters/*.toml), each checked where it is read.
void read_inverter_fields(const View& v, InverterParams* p)
{
    const struct {
        const char* key;
        double* dst;
    } nums[] = {{"f_pwm_Hz", &p->f_pwm_Hz},         {"dead_time_s", &p->dead_time_s},
                {"t_on_s", &p->t_on_s},             {"t_off_s", &p->t_off_s},
                {"v_switch_V", &p->v_switch_V},     {"r_switch_Ohm", &p->r_switch_Ohm},
                {"v_diode_V", &p->v_diode_V},       {"r_diode_Ohm", &p->r_diode_Ohm},
                {"min_pulse_s", &p->min_pulse_s},   {"i_transition_A", &p->i_transition_A}};
    for (const auto& n : nums) {
        if (const auto x = v.number(n.key)) {
            if (std::string(n.key) == "f_pwm_Hz") {
                gt(v, n.key, *x, 0.0);
            } else {
                ge(v, n.key, *x, 0.0);
            }
            *n.dst = *x;
        }
    }
    if (const auto b = v.boolean("synchronous")) {
        p->synchronous = *b;
    }
}

const std::vector<std::string>& inverter_file_keys()
{
    static const std::vector<std::string> k = {"name",         "source",      "description", "f_pwm_Hz",
                                               "dead_time_s",  "t_on_s",      "t_off_s",     "v_switch_V",
                                               "r_switch_Ohm", "v_diode_V",   "r_diode_Ohm", "min_pulse_s",
                                               "i_transition_A", "synchronous"};
    return k;
}

// [inverter] (optional): the MCU board's PWM inverter (model/inverter.h)
// in place of the amplifier model: an inverter file and/or the keys, the
// table's over the file's; absent: the amplifier (today's plant).
void read_inverter(const View* v, Scenario* sc)
{
    if (v == nullptr) {
        return;
    }
    v->only(table_keys("inverter"));
    InverterParams p;
    if (const auto file = v->string("file")) {
        fs::path ip(*file);
        if (ip.is_relative()) {
            ip = fs::path(sc->path).parent_path() / ip;
        }
        sc->inverter_file = ip.lexically_normal().string();
        std::error_code ec;
        if (!fs::is_regular_file(sc->inverter_file, ec)) {
            v->fail("file", "cannot open inverter file '" + sc->inverter_file + "'");
        }
        const toml::table t = parse_toml(sc->inverter_file);
        const View f(t, sc->inverter_file, "");
        f.only(inverter_file_keys());
        f.string("name");
        f.string("source");
        f.string("description");
        read_inverter_fields(f, &p);
    }
    read_inverter_fields(*v, &p);
    if (const char* why = p.problem()) {
        // the combinations (each value was checked on its own above)
        v->fail(p.min_pulse_s * 2.0 * p.f_pwm_Hz >= 1.0 ? "min_pulse_s" : "dead_time_s",
                std::string(why) + " (1/f_pwm_Hz = " + fmt_num(1.0 / p.f_pwm_Hz) + " s)");
    }
    // pwm: the averaged legs (default) or the legs switched at the carrier
    // (model/switched_pwm.h), which needs a whole number of carrier periods
    // per control period ([run] is read before this table)
    if (const auto m = v->string("pwm")) {
        if (*m == "switched") {
            p.pwm = PwmModel::kSwitched;
        } else if (*m != "averaged") {
            v->fail("pwm", "must be \"averaged\" or \"switched\" (got \"" + *m + "\")");
        }
    }
    if (p.pwm == PwmModel::kSwitched && SwitchedPwm::carrier_periods(p.f_pwm_Hz, sc->ts_s) == 0) {
        v->fail("pwm", "\"switched\" needs a whole number (1 to " + std::to_string(SwitchedPwm::kMaxCarrierPeriods) +
                           ") of PWM periods per control period: f_pwm_Hz = " + fmt_num(p.f_pwm_Hz) +
                           " Hz is " + fmt_num(p.f_pwm_Hz * sc->ts_s) + " times the control rate 1/run.Ts_s = " +
                           fmt_num(1.0 / sc->ts_s) + " Hz");
    }
    sc->inverter = p;
    sc->inverter_given = true;
    sc->inverter_compensation = v->boolean("compensation").value_or(true);
    if (const auto t = v->number("compensation_dead_time_s")) {
        ge(*v, "compensation_dead_time_s", *t, 0.0);
        if (!(2.0 * (*t + p.t_on_s - p.t_off_s) * p.f_pwm_Hz < 1.0)) {
            v->fail("compensation_dead_time_s", "must be shorter than half the PWM period (1/f_pwm_Hz = " +
                                                    fmt_num(1.0 / p.f_pwm_Hz) + " s)");
        }
        sc->compensation_dead_time_s = *t;
    }
}

// The scenario's tables in the order they are read (a table may use what
// the ones before it set), each by its parser; a required one's absence is
// an error naming it. The drive's own tables come after them all (its host
// part's parse).
struct Section {
    const char* table;
    bool required;
    void (*read)(const View* t, Scenario* sc);  // t: nullptr when absent (never when required)
};
const Section kSections[] = {
    {"run", true, &read_run},
    {"motor", true, &read_motor},
    {"drive_model", false, &read_drive_model},
    {"supply", true, &read_supply},
    {"limits", true, &read_limits},
    {"sensor", false, &read_sensor},
    {"faults", false, &read_faults},
    {"load", false, &read_load},
    {"expect", false, &read_expect},
    {"board", false, &read_board},
    {"encoder", false, &read_encoder},
    {"inverter", false, &read_inverter},
};

// [drive]: the scenario's drive, a drive of the host registry
// (sim/host_drives/) with its table: [drive] kind, or without it the drive
// whose table the scenario has ([trajectory] if none: the position
// drive's, which its parser then requires). Checked before any other
// table; sets sc->drive_kind and sc->drive_table.
const HostDrive* read_drive(const View& root, Scenario* sc)
{
    // One drive's table: the papers' tables choose their drive without
    // [drive] (so two of them are a mistake)
    {
        std::string tables, second;
        int n_tables = 0;
        for (const HostDrive* d : host_drives()) {
            tables += (tables.empty() ? "" : ", ") + std::string("[") + d->table + "] (" + d->name + ")";
            if (!d->needs_kind && root.has(d->table)) {
                n_tables += 1;
                second = d->table;
            }
        }
        if (n_tables > 1) {
            root.fail(second, "a scenario has one of " + tables);
        }
    }
    const HostDrive* host = nullptr;
    if (const auto v = root.table("drive")) {
        v->only(table_keys("drive"));
        const auto k = v->string("kind");
        if (!k) {
            v->fail("kind", "missing required field");
        }
        host = host_drive_find(*k);
        if (host == nullptr) {
            std::string known;
            for (const HostDrive* d : host_drives()) {
                known += (known.empty() ? "" : ", ") + std::string("\"") + d->name + "\"";
            }
            v->fail("kind", "\"" + *k + "\" is not a drive of the registry (known: " + known + ")");
        }
        for (const HostDrive* d : host_drives()) {
            if (d != host && root.has(d->table)) {
                v->fail("kind", "\"" + *k + "\" reads [" + host->table + "]; [" + d->table + "] is the table of \"" +
                                    d->name + "\"");
            }
        }
    } else {
        for (const HostDrive* d : host_drives()) {
            if (d->needs_kind && root.has(d->table)) {
                root.fail(d->table, std::string("only with [drive] kind = \"") + d->name + "\"");
            }
        }
        for (const HostDrive* d : host_drives()) {
            if (host == nullptr && root.has(d->table)) {
                host = d;
            }
        }
        if (host == nullptr) {
            host = host_drive_of_table("trajectory");
        }
    }
    if (host == nullptr) {
        root.fail("drive", "no drive of the registry reads [trajectory], and the scenario names none");
    }
    sc->drive_kind = host->name;
    sc->drive_table = host->table;
    return host;
}

}  // namespace

Scenario load_scenario(const std::string& path)
{
    Scenario sc;
    sc.path = path;
    sc.stem = fs::path(path).stem().string();

    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        throw ScenarioError(path + ": cannot open scenario file");
    }
    const toml::table root_t = parse_toml(path);
    const View root(root_t, path, "");
    root.only(top_level_keys());
    const HostDrive* host = read_drive(root, &sc);
    sc.description = root.string("description").value_or("");
    for (const Section& s : kSections) {
        const auto t = root.table(s.table);
        if (!t && s.required) {
            root.fail(s.table, "missing required table");
        }
        s.read(t ? &*t : nullptr, &sc);
    }
    // the drives' further tables, then the drive's own table (after every
    // shared table they may read): their host parts' (host_drive.h)
    for (const HostDrive* d : host_drives()) {
        if (d->parse_extra != nullptr) {
            d->parse_extra(root, &sc);
        }
    }
    const auto t = root.table(host->table);
    host->parse(t ? &*t : nullptr, &sc);
    return sc;
}

}  // namespace mcsim

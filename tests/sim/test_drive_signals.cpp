// The drives' signals (firmware/drives/drive.h: drive_signal_t, the
// operations signals and read_signals), for every registered drive
// designed from every shipped scenario of it (sim/scenarios/, with the
// configurations they hold: paper 002's encoder, HF injection and its own
// start): the list is well-formed (names unique, letters, digits and _,
// units and descriptions given, at most DRIVE_SIGNALS_MAX), the same on
// every call, read_signals fills exactly its count of values, and every
// value after init is finite. motorsim's CSV columns and metric inputs are
// these names (sim/motorsim/drive_signals.h).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "host_drives/host_drive.h"
#include "mc_convert.h"
#include "scenario/scenario.h"

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> scenarios()
{
    std::vector<fs::path> out;
    for (const char* dir : {"sim/scenarios", "tests/sim/design_runs"}) {
        for (const auto& e : fs::directory_iterator(fs::path(MC_SOURCE_DIR) / dir)) {
            if (e.path().extension() == ".toml") {
                out.push_back(e.path());
            }
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

bool name_ok(const char* n)
{
    if (n == nullptr || !std::isalpha(static_cast<unsigned char>(n[0]))) {
        return false;
    }
    for (; *n != '\0'; ++n) {
        if (!std::isalnum(static_cast<unsigned char>(*n)) && *n != '_') {
            return false;
        }
    }
    return true;
}

// Every check of one initialised drive; where names the run in failures.
void check_signals(const drive_t& d, const std::string& where)
{
    ASSERT_NE(d.ops->signals, nullptr) << where;
    ASSERT_NE(d.ops->read_signals, nullptr) << where;
    std::uint32_t n = 0;
    const drive_signal_t* list = drive_signals(&d, &n);
    ASSERT_LE(n, DRIVE_SIGNALS_MAX) << where;
    ASSERT_TRUE(n == 0 || list != nullptr) << where;
    std::set<std::string> names;
    for (std::uint32_t k = 0; k < n; ++k) {
        const drive_signal_t& s = list[k];
        EXPECT_TRUE(name_ok(s.name)) << where << ": signal " << k << " '" << (s.name ? s.name : "(null)") << "'";
        if (s.name == nullptr) {
            continue;
        }
        EXPECT_TRUE(names.insert(s.name).second) << where << ": '" << s.name << "' listed twice";
        EXPECT_TRUE(s.unit != nullptr && s.unit[0] != '\0') << where << ": '" << s.name << "' has no unit";
        EXPECT_TRUE(s.description != nullptr && s.description[0] != '\0')
            << where << ": '" << s.name << "' has no description";
        EXPECT_EQ(s.flags & ~static_cast<unsigned>(DRIVE_SIGNAL_INTEGER | DRIVE_SIGNAL_SETTING), 0u)
            << where << ": '" << s.name << "' has an unknown flag";
    }
    // the same list on every call
    std::uint32_t n2 = 0;
    EXPECT_EQ(drive_signals(&d, &n2), list) << where;
    EXPECT_EQ(n2, n) << where;
    // read_signals fills values[0 .. n) and nothing beyond
    constexpr unsigned char kFill = 0xA5;
    mc_t v[DRIVE_SIGNALS_MAX + 1];
    std::memset(v, kFill, sizeof v);
    drive_read_signals(&d, v);
    for (std::uint32_t k = n; k < DRIVE_SIGNALS_MAX + 1; ++k) {
        const auto* b = reinterpret_cast<const unsigned char*>(&v[k]);
        bool untouched = true;
        for (std::size_t j = 0; j < sizeof(mc_t); ++j) {
            untouched = untouched && b[j] == kFill;
        }
        EXPECT_TRUE(untouched) << where << ": read_signals wrote value " << k << ", beyond its " << n << " signals";
    }
    for (std::uint32_t k = 0; k < n; ++k) {
        const auto* b = reinterpret_cast<const unsigned char*>(&v[k]);
        bool untouched = true;
        for (std::size_t j = 0; j < sizeof(mc_t); ++j) {
            untouched = untouched && b[j] == kFill;
        }
        EXPECT_FALSE(untouched) << where << ": read_signals left '" << list[k].name << "' unwritten";
        const double x = mcsim::to_double(v[k]);
        EXPECT_TRUE(std::isfinite(x)) << where << ": '" << list[k].name << "' = " << x << " after init";
        if ((list[k].flags & DRIVE_SIGNAL_INTEGER) != 0) {
            EXPECT_EQ(x, std::round(x)) << where << ": '" << list[k].name << "' is an integer signal";
        }
    }
}

TEST(DriveSignals, EveryDriveFromEveryScenario)
{
    std::map<std::string, int> designed;  // per registered drive: configurations checked
    for (const fs::path& f : scenarios()) {
        std::unique_ptr<mcsim::Scenario> sc;
        try {
            sc = std::make_unique<mcsim::Scenario>(mcsim::load_scenario(f.string()));
        } catch (const std::exception&) {
            continue;  // a scenario of another build (paper 002's in the fixed-point one)
        }
        auto storage = std::make_unique<drive_storage_t>();
        auto cfg = std::make_unique<drive_config_storage_t>();
        drive_t d{};
        try {
            d = mcsim::design_scenario_drive(*sc, storage.get(), cfg.get());
        } catch (const std::exception&) {
            continue;  // its design refused in this build
        }
        check_signals(d, f.filename().string() + " (" + sc->drive_kind + ")");
        designed[sc->drive_kind] += 1;
    }
    for (std::size_t k = 0; k < drive_registry_count; ++k) {
        const std::string name = drive_registry[k]->name;
        if (MC_FIXED && name == "paper002") {
            continue;  // float only (docs/paper002.md)
        }
        EXPECT_GT(designed[name], 0) << name << ": no shipped scenario designed it";
    }
}

// A drive's list can depend on its configuration (drive.h): paper 002's
// injection signals with the HF injection, its start's with its own start.
TEST(DriveSignals, ListFollowsTheConfiguration)
{
    if (MC_FIXED) {
        GTEST_SKIP() << "paper 002's drive is float only";
    }
    std::map<std::string, std::uint32_t> count;
    for (const char* stem : {"paper002_reference", "ipmsm_zero_speed", "ipmsm_hfi_start16"}) {
        mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/" + stem + ".toml");
        auto storage = std::make_unique<drive_storage_t>();
        auto cfg = std::make_unique<drive_config_storage_t>();
        const drive_t d = mcsim::design_scenario_drive(sc, storage.get(), cfg.get());
        const drive_signal_t* list = drive_signals(&d, &count[stem]);
        std::set<std::string> names;
        for (std::uint32_t k = 0; k < count[stem]; ++k) {
            names.insert(list[k].name);
        }
        const bool hfi = std::string(stem) != "paper002_reference";
        EXPECT_EQ(names.count("ekf_P_44"), 1u) << stem;
        EXPECT_EQ(names.count("hfi_on"), hfi ? 1u : 0u) << stem;
        EXPECT_EQ(names.count("hfi_start_polarity"), std::string(stem) == "ipmsm_hfi_start16" ? 1u : 0u) << stem;
    }
    EXPECT_LT(count["paper002_reference"], count["ipmsm_zero_speed"]);
    EXPECT_LT(count["ipmsm_zero_speed"], count["ipmsm_hfi_start16"]);
}

}  // namespace

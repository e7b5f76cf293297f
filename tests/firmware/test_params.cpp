// firmware.Params.*: the parameters' C API (firmware/config/params.h) over
// the generated tables (tools/params/gen_params.py from each drive's
// params.toml and config/board_params.toml): find and list by id, the
// value's type and range, the access rule, set and get in a design input;
// and the defaults designing exactly today's images: each drive's design
// input from its table's defaults, designed by the host design (design/),
// is the configuration its board file designs through the scenario path
// (sim/host_drives/; tools/bench/pil_gen.cpp --board-params checks the
// same for the values it writes), byte for byte; and again after every value went
// through its 32 bits and back (a CAN read and write, the store).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "host_drives/host_drive.h"
#include "scenario/scenario.h"

extern "C" {
#include "comm/can_tx.h"
#include "config/board_params.h"
#include "config/generated/board_params.h"
#include "config/params.h"
#include "design/ops/drive_design_ops.h"
#include "design/paper000_design.h"
#include "design/paper001_design.h"
#include "design/paper002_design.h"
#include "design/sensored_foc_design.h"
#include "drives/paper000/generated/paper000_params.h"
#include "drives/paper001/generated/paper001_params.h"
#include "drives/paper002/generated/paper002_params.h"
#include "drives/registry.h"
#include "drives/sensored_foc/generated/sensored_foc_params.h"
}

namespace {

const param_table_t* const kDriveTables[] = {&paper000_params, &paper001_params, &paper002_params,
                                             &sensored_foc_params};
const param_table_t* const kBoardTables[] = {&board_params_vesc6, &board_params_odrive36,
                                             &board_params_qemu_netduinoplus2};

param_value_t f32v(float x)
{
    param_value_t v;
    v.f32 = x;
    return v;
}
param_value_t i32v(int32_t x)
{
    param_value_t v;
    v.i32 = x;
    return v;
}
param_value_t u32v(uint32_t x)
{
    param_value_t v;
    v.u32 = x;
    return v;
}

TEST(Params, TablesAreConsistent)
{
    for (const param_table_t* t : kDriveTables) {
        param_error_t e{};
        EXPECT_TRUE(params_table_check(t, &e)) << t->name << ": 0x" << std::hex << e.id << " " << e.text;
        EXPECT_GT(t->n_params, 10u) << t->name;
        EXPECT_GE(t->params[0].id, PARAM_ID_DRIVE_FIRST) << t->name;
    }
    for (const param_table_t* t : kBoardTables) {
        param_error_t e{};
        EXPECT_TRUE(params_table_check(t, &e)) << t->name << ": 0x" << std::hex << e.id << " " << e.text;
        EXPECT_LE(t->params[t->n_params - 1].id, PARAM_ID_BOARD_LAST);
        EXPECT_EQ(t->target_bytes, sizeof(board_params_t));
    }
    EXPECT_EQ(paper001_params.target_bytes, sizeof(p001_design_input_t));
    EXPECT_EQ(paper001_params.schema_hash, PAPER001_PARAMS_SCHEMA_HASH);
    // the boards' tables differ in their defaults only: different schemas
    EXPECT_NE(board_params_vesc6.schema_hash, board_params_odrive36.schema_hash);
    EXPECT_EQ(board_params_vesc6.params[0].def_hash, board_params_odrive36.params[0].def_hash);
    // the same parameter, the same definition in every drive
    const param_desc_t* a = params_find(&paper000_params, PAPER001_PARAMS_R_OHM, nullptr);
    const param_desc_t* b = params_find(&paper001_params, PAPER001_PARAMS_R_OHM, nullptr);
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(a->def_hash, b->def_hash);
    EXPECT_STREQ(a->name, "R_ohm");

    // a broken table is refused, naming the parameter
    param_desc_t broken[2] = {paper001_params.params[1], paper001_params.params[0]};  // ids descending
    param_table_t t = paper001_params;
    t.params = broken;
    t.n_params = 2;
    param_error_t e{};
    EXPECT_FALSE(params_table_check(&t, &e));
    EXPECT_STREQ(e.text, "ids not ascending");
    broken[0] = paper001_params.params[0];
    broken[1] = paper001_params.params[1];
    broken[1].field = PARAM_FIELD_INT;  // an f32 into an int
    EXPECT_FALSE(params_table_check(&t, &e));
    EXPECT_STREQ(e.text, "field type unfit");
    broken[1] = paper001_params.params[1];
    broken[1].offset = paper001_params.target_bytes;
    EXPECT_FALSE(params_table_check(&t, &e));
    EXPECT_STREQ(e.text, "field outside the struct");
}

TEST(Params, FindAndList)
{
    param_error_t e{};
    const param_desc_t* d = params_find(&paper001_params, PAPER001_PARAMS_I_MAX_A, &e);
    ASSERT_NE(d, nullptr);
    EXPECT_STREQ(d->name, "i_max_A");
    EXPECT_STREQ(d->unit, "A");
    EXPECT_EQ(d->type, PARAM_F32);
    EXPECT_EQ(d->access, PARAM_DISABLED);
    EXPECT_EQ(e.status, PARAM_OK);
    for (const param_table_t* t : kDriveTables) {
        for (uint16_t k = 0; k < t->n_params; ++k) {
            EXPECT_EQ(params_find(t, t->params[k].id, nullptr), &t->params[k]) << t->name << " " << t->params[k].name;
        }
    }
    // unknown: a board id in a drive's table, an id between two, the end
    for (uint16_t id : {uint16_t{0x0001}, uint16_t{0x0100}, uint16_t{0x0104}, uint16_t{0xFFFF}}) {
        EXPECT_EQ(params_find(&paper001_params, id, &e), nullptr) << id;
        EXPECT_EQ(e.status, PARAM_ERR_UNKNOWN_ID);
        EXPECT_EQ(e.id, id);
        EXPECT_STREQ(params_status_name(e.status), "unknown_id");
    }
    // list: the walk from 0 visits every parameter once, in id order
    uint16_t n = 0;
    for (const param_desc_t* p = params_next(&paper002_params, 0); p != nullptr;
         p = p->id == 0xFFFE ? nullptr : params_next(&paper002_params, static_cast<uint16_t>(p->id + 1))) {
        EXPECT_EQ(p, &paper002_params.params[n]);
        ++n;
    }
    EXPECT_EQ(n, paper002_params.n_params);
}

TEST(Params, ValuesOfTheirTypeAndRange)
{
    p001_design_input_t in{};
    p001_design_defaults(&in);
    param_error_t e{};
    ASSERT_TRUE(params_set_defaults(&paper001_params, &in, &e));
    const p001_design_input_t before = in;
    struct Case {
        uint16_t id;
        param_value_t v;
        param_status_t want;
    };
    const float inf = std::numeric_limits<float>::infinity();
    const Case refused[] = {
        {PAPER001_PARAMS_I_MAX_A, f32v(150.5f), PARAM_ERR_OUT_OF_RANGE},  // max 150
        {PAPER001_PARAMS_I_MAX_A, f32v(0.05f), PARAM_ERR_OUT_OF_RANGE},   // min 0.1
        {PAPER001_PARAMS_I_MAX_A, f32v(-8.0f), PARAM_ERR_OUT_OF_RANGE},
        {PAPER001_PARAMS_R_OHM, f32v(std::nanf("")), PARAM_ERR_BAD_VALUE},
        {PAPER001_PARAMS_R_OHM, f32v(inf), PARAM_ERR_BAD_VALUE},
        {PAPER001_PARAMS_N_P, i32v(0), PARAM_ERR_OUT_OF_RANGE},
        {PAPER001_PARAMS_N_P, i32v(101), PARAM_ERR_OUT_OF_RANGE},
        {PAPER001_PARAMS_I_TRIP_SAMPLES, i32v(-1), PARAM_ERR_OUT_OF_RANGE},
        {PAPER001_PARAMS_TRACK_RESISTANCE, u32v(2), PARAM_ERR_BAD_VALUE},
        {PAPER001_PARAMS_ESTIMATOR, i32v(2), PARAM_ERR_BAD_VALUE},  // flux, back_emf
        {PAPER001_PARAMS_ESTIMATOR, i32v(-1), PARAM_ERR_BAD_VALUE},
        {0x0104, f32v(1e-3f), PARAM_ERR_UNKNOWN_ID},  // L_q_H: not paper 001's
    };
    for (const Case& c : refused) {
        EXPECT_FALSE(params_write(&paper001_params, &in, c.id, c.v, false, &e)) << std::hex << c.id;
        EXPECT_EQ(e.status, c.want) << std::hex << c.id << ": " << e.text;
        EXPECT_EQ(e.id, c.id);
        EXPECT_EQ(std::memcmp(&in, &before, sizeof in), 0) << "a refused write changed the input";
    }
    EXPECT_STREQ(params_status_name(PARAM_ERR_OUT_OF_RANGE), "out_of_range");
    EXPECT_STREQ(params_status_name(PARAM_ERR_BAD_VALUE), "bad_value");
    // the range's edges are in it
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_I_MAX_A, f32v(150.0f), false, &e)) << e.text;
    EXPECT_EQ(in.i_max_A, 150.0);
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_I_MAX_A, f32v(0.1f), false, &e)) << e.text;
    EXPECT_EQ(in.i_max_A, static_cast<double>(0.1f));  // not the default: the float32 widened
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_N_P, i32v(100), false, &e));
    EXPECT_EQ(in.motor.n_p, 100);
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_ESTIMATOR, i32v(1), false, &e));
    EXPECT_EQ(in.estimator, OPEN_START_BACK_EMF);
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_TRACK_RESISTANCE, u32v(1), false, &e));
    EXPECT_TRUE(in.track_resistance);
    // an integer field wider than int32 (paper 002's encoder counts: long)
    p002_design_input_t in2{};
    EXPECT_TRUE(params_write(&paper002_params, &in2, PAPER002_PARAMS_ENCODER_COUNTS, i32v(1 << 24), false, &e));
    EXPECT_EQ(in2.encoder_counts, 1L << 24);
}

TEST(Params, AccessRule)
{
    p001_design_input_t in{};
    param_error_t e{};
    ASSERT_TRUE(params_set_defaults(&paper001_params, &in, &e));
    // read-only: never, enabled or not
    for (bool enabled : {false, true}) {
        EXPECT_FALSE(params_write(&paper001_params, &in, PAPER001_PARAMS_TS_S, f32v(1e-4f), enabled, &e));
        EXPECT_EQ(e.status, PARAM_ERR_READ_ONLY);
        EXPECT_STREQ(params_status_name(e.status), "read_only");
    }
    EXPECT_EQ(in.ts_s, 1e-4);
    // only while disabled
    EXPECT_FALSE(params_write(&paper001_params, &in, PAPER001_PARAMS_R_OHM, f32v(0.3f), true, &e));
    EXPECT_EQ(e.status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_STREQ(params_status_name(e.status), "not_while_enabled");
    EXPECT_EQ(in.motor.R_ohm, 0.225);
    EXPECT_TRUE(params_write(&paper001_params, &in, PAPER001_PARAMS_R_OHM, f32v(0.3f), false, &e));
    EXPECT_EQ(in.motor.R_ohm, static_cast<double>(0.3f));
    // the access rule comes before the range: a read-only refusal says so
    EXPECT_FALSE(params_write(&paper001_params, &in, PAPER001_PARAMS_TS_S, f32v(1.0f), false, &e));
    EXPECT_EQ(e.status, PARAM_ERR_READ_ONLY);
    // live: at any time (the board's telemetry periods)
    board_params_t b{};
    ASSERT_TRUE(params_set_defaults(&board_params_vesc6, &b, &e));
    EXPECT_TRUE(params_write(&board_params_vesc6, &b, BOARD_PARAMS_TLM_VELOCITY_MS, u32v(20), true, &e));
    EXPECT_EQ(b.tlm_period_ms[2], 20u);
    EXPECT_FALSE(params_write(&board_params_vesc6, &b, BOARD_PARAMS_TLM_VELOCITY_MS, u32v(60001), true, &e));
    EXPECT_EQ(e.status, PARAM_ERR_OUT_OF_RANGE);
    EXPECT_FALSE(params_write(&board_params_vesc6, &b, BOARD_PARAMS_CAN_NODE, u32v(3), true, &e));
    EXPECT_EQ(e.status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_FALSE(params_write(&board_params_vesc6, &b, BOARD_PARAMS_CAN_NODE, u32v(16), false, &e));
    EXPECT_EQ(e.status, PARAM_ERR_OUT_OF_RANGE);
    // no table, no target: a bad request
    EXPECT_FALSE(params_write(&paper001_params, nullptr, PAPER001_PARAMS_R_OHM, f32v(0.3f), false, &e));
    EXPECT_EQ(e.status, PARAM_ERR_BAD_REQUEST);
    EXPECT_EQ(params_find(nullptr, 1, &e), nullptr);
    EXPECT_EQ(e.status, PARAM_ERR_BAD_REQUEST);
}

TEST(Params, ReadAndDefaultsAsTheyTravel)
{
    p002_design_input_t in{};
    param_error_t e{};
    ASSERT_TRUE(params_set_defaults(&paper002_params, &in, &e));
    EXPECT_EQ(in.motor.L_H, 3e-3);
    EXPECT_EQ(in.motor.L_q_H, 9e-3);
    EXPECT_EQ(in.motor.K_Nm_per_A, 0.16);
    EXPECT_EQ(in.encoder_counts, 8192L);
    EXPECT_EQ(in.angle_source, P002_ANGLE_ENCODER);
    EXPECT_TRUE(in.compensate);
    EXPECT_EQ(in.w1_rad_s, 0.0);  // fixed: at rest
    param_value_t v{};
    ASSERT_TRUE(params_read(&paper002_params, &in, PAPER002_PARAMS_R_OHM, &v, &e));
    EXPECT_EQ(v.f32, 0.3f);
    ASSERT_TRUE(params_read(&paper002_params, &in, PAPER002_PARAMS_ENCODER_COUNTS, &v, &e));
    EXPECT_EQ(v.i32, 8192);
    ASSERT_TRUE(params_read(&paper002_params, &in, PAPER002_PARAMS_COMPENSATE, &v, &e));
    EXPECT_EQ(v.u32, 1u);
    // the default's float32 written back is the default's exact double
    // (0.3f is 0.30000001192...): what makes a stored default design the same
    ASSERT_TRUE(params_write(&paper002_params, &in, PAPER002_PARAMS_R_OHM, f32v(0.3f), false, &e));
    EXPECT_EQ(in.motor.R_ohm, 0.3);
    ASSERT_TRUE(params_write(&paper002_params, &in, PAPER002_PARAMS_R_OHM, f32v(0.31f), false, &e));
    EXPECT_EQ(in.motor.R_ohm, static_cast<double>(0.31f));
    EXPECT_FALSE(params_read(&paper002_params, &in, 0x0999, &v, &e));
    EXPECT_EQ(e.status, PARAM_ERR_UNKNOWN_ID);
}

// ---- the defaults design today's images ------------------------------------

std::string src(const char* rel) { return std::string(MC_SOURCE_DIR) + "/" + rel; }

// What the board file designs: the scenario path of the images' generator.
std::unique_ptr<drive_config_storage_t> scenario_config(const char* rel, mcsim::Scenario* keep = nullptr)
{
    mcsim::Scenario sc = mcsim::load_scenario(src(rel));
    auto cfg = std::make_unique<drive_config_storage_t>();
    std::memset(cfg.get(), 0, sizeof *cfg);
    const mcsim::HostDrive* host = mcsim::host_drive_find(sc.drive_kind);
    EXPECT_NE(host, nullptr);
    host->design(sc, cfg.get());
    if (keep != nullptr) *keep = sc;
    return cfg;
}

// Every value through its 32 bits and back, as a CAN read and write (or a
// store's save and load) would take it.
template <typename In>
void round_trip(const param_table_t* t, In* in)
{
    for (uint16_t k = 0; k < t->n_params; ++k) {
        const param_desc_t* d = &t->params[k];
        if (d->access == PARAM_RO) continue;
        param_value_t v{};
        param_error_t e{};
        ASSERT_TRUE(params_read(t, in, d->id, &v, &e)) << d->name;
        ASSERT_TRUE(params_write(t, in, d->id, v, false, &e)) << d->name << ": " << e.text;
    }
}

void expect_same_config(const void* a, const void* b, const char* drive, const char* what)
{
    const drive_ops_t* ops = drive_find(drive);
    ASSERT_NE(ops, nullptr);
    const auto* pa = static_cast<const unsigned char*>(a);
    const auto* pb = static_cast<const unsigned char*>(b);
    uint32_t diff = 0, first = ops->config_bytes;
    for (uint32_t k = 0; k < ops->config_bytes; ++k) {
        if (pa[k] != pb[k]) {
            ++diff;
            if (first == ops->config_bytes) first = k;
        }
    }
    EXPECT_EQ(diff, 0u) << drive << " " << what << ": " << diff << " of " << ops->config_bytes
                        << " bytes differ, the first at " << first;
}

TEST(Params, DefaultsDesignThePaper001Vesc6Image)
{
    auto want = scenario_config("firmware/drives/paper001/boards/vesc6.toml");
    for (int pass = 0; pass < 2; ++pass) {
        p001_design_input_t in{};
        p001_design_defaults(&in);
        param_error_t e{};
        ASSERT_TRUE(params_set_defaults(&paper001_params, &in, &e));
        if (pass == 1) round_trip(&paper001_params, &in);
        auto got = std::make_unique<drive_config_storage_t>();
        std::memset(got.get(), 0, sizeof *got);
        p001_design_report_t rep{};
        char err[256] = {0};
        ASSERT_TRUE(p001_design(&in, &got->paper001, &rep, err, sizeof err)) << err;
        expect_same_config(got.get(), want.get(), "paper001", pass == 0 ? "defaults" : "defaults round-tripped");
    }
}

TEST(Params, DefaultsDesignThePaper000Odrive36Image)
{
    auto want = scenario_config("firmware/drives/paper000/boards/odrive36.toml");
    for (int pass = 0; pass < 2; ++pass) {
        drive_design_input_t in{};
        drive_design_defaults(&in);
        param_error_t e{};
        ASSERT_TRUE(params_set_defaults(&paper000_params, &in, &e));
        if (pass == 1) round_trip(&paper000_params, &in);
        auto got = std::make_unique<drive_config_storage_t>();
        std::memset(got.get(), 0, sizeof *got);
        char err[256] = {0};
        ASSERT_TRUE(drive_design(&in, &got->paper000, err, sizeof err)) << err;
        expect_same_config(got.get(), want.get(), "paper000", pass == 0 ? "defaults" : "defaults round-tripped");
    }
}

TEST(Params, DefaultsDesignThePaper002Vesc6Images)
{
    // the encoder image: the defaults; the sensorless one: two values changed
    for (const char* board :
         {"firmware/drives/paper002/boards/vesc6.toml", "firmware/drives/paper002/boards/vesc6_sensorless.toml"}) {
        const bool sensorless = std::strstr(board, "sensorless") != nullptr;
        auto want = scenario_config(board);
        for (int pass = 0; pass < 2; ++pass) {
            p002_design_input_t in{};
            p002_design_defaults(&in);
            param_error_t e{};
            ASSERT_TRUE(params_set_defaults(&paper002_params, &in, &e));
            if (sensorless) {
                ASSERT_TRUE(params_write(&paper002_params, &in, PAPER002_PARAMS_ANGLE_SOURCE, i32v(P002_ANGLE_FLUX),
                                         false, &e));
                ASSERT_TRUE(params_write(&paper002_params, &in, PAPER002_PARAMS_ENCODER_COUNTS, i32v(0), false, &e));
            }
            if (pass == 1) round_trip(&paper002_params, &in);
            auto got = std::make_unique<drive_config_storage_t>();
            std::memset(got.get(), 0, sizeof *got);
            char err[256] = {0};
            ASSERT_TRUE(p002_design(&in, &got->paper002, err, sizeof err)) << err;
            expect_same_config(got.get(), want.get(), "paper002", board);
        }
    }
}

TEST(Params, DefaultsDesignTheSensoredFocBenchmark)
{
    // no board runs it: its defaults are sim/scenarios/sensored_benchmark.toml's,
    // whose speed profile (not a parameter) is copied over
    mcsim::Scenario sc;
    auto want = scenario_config("sim/scenarios/sensored_benchmark.toml", &sc);
    sfoc_design_input_t in{};
    sfoc_design_defaults(&in);
    param_error_t e{};
    ASSERT_TRUE(params_set_defaults(&sensored_foc_params, &in, &e));
    round_trip(&sensored_foc_params, &in);
    in.n_points = sc.speed_points.size();
    for (std::size_t k = 0; k < sc.speed_points.size(); ++k) {
        in.t_s[k] = sc.speed_points[k].first;
        in.omega_rad_s[k] = sc.speed_points[k].second;
    }
    auto got = std::make_unique<drive_config_storage_t>();
    std::memset(got.get(), 0, sizeof *got);
    char err[256] = {0};
    ASSERT_TRUE(sfoc_design(&in, &got->sensored_foc, err, sizeof err)) << err;
    expect_same_config(got.get(), want.get(), "sensored_foc", "defaults");
}

// Each drive's design as an image runs it (design/ops/drive_design_ops.h):
// its sizes the drive's, and the defaults it derives designed into what
// the drive's board file designs on the host (what the STM32 images
// compare their design on the board with).
TEST(Params, DesignOpsDesignEachDrivesDefaults)
{
    const struct {
        const drive_design_ops_t* ops;
        const char* board;  // nullptr: no board runs it
    } cases[] = {{drive_design_ops_find("paper000"), "firmware/drives/paper000/boards/odrive36.toml"},
                 {drive_design_ops_find("paper001"), "firmware/drives/paper001/boards/vesc6.toml"},
                 {drive_design_ops_find("paper002"), "firmware/drives/paper002/boards/vesc6.toml"},
                 {drive_design_ops_find("sensored_foc"), nullptr}};
    for (const auto& c : cases) {
        ASSERT_NE(c.ops, nullptr);
        const drive_ops_t* ops = drive_find(c.ops->name);
        ASSERT_NE(ops, nullptr) << c.ops->name;
        EXPECT_EQ(c.ops->config_bytes, ops->config_bytes) << c.ops->name;
        if (c.board == nullptr) continue;
        std::vector<unsigned char> in(c.ops->input_bytes);
        param_error_t e{};
        ASSERT_TRUE(drive_design_defaults_input(c.ops, in.data(), &e)) << e.text;
        auto got = std::make_unique<drive_config_storage_t>();
        std::memset(got.get(), 0, sizeof *got);
        char err[256] = {0};
        ASSERT_TRUE(c.ops->design(in.data(), got.get(), err, sizeof err)) << c.ops->name << ": " << err;
        expect_same_config(got.get(), scenario_config(c.board).get(), c.ops->name, "design ops");
    }
}

TEST(Params, AChangedParameterReachesTheDesign)
{
    // every writable f32 parameter of paper 001 moved by 10 % within its
    // range changes the designed configuration, or the design refuses it
    // naming a field: the table's offsets point where the design reads
    auto design = [](const p001_design_input_t& in, drive_config_storage_t* cfg, std::string* why) {
        std::memset(cfg, 0, sizeof *cfg);
        p001_design_report_t rep{};
        char err[256] = {0};
        const bool ok = p001_design(&in, &cfg->paper001, &rep, err, sizeof err);
        *why = err;
        return ok;
    };
    p001_design_input_t base{};
    p001_design_defaults(&base);
    ASSERT_TRUE(params_set_defaults(&paper001_params, &base, nullptr));
    auto ref = std::make_unique<drive_config_storage_t>();
    std::string why;
    ASSERT_TRUE(design(base, ref.get(), &why)) << why;
    const char* unread[] = {
        "omega_lim_rad_s", "handover_sweep_rad", "a1",           "a2", "damping_r_ohm",
        "blend_tau_s",     "fit_det_min",        "i_open_loop_A"};  // 0: derived; a derived value is not read
    for (uint16_t k = 0; k < paper001_params.n_params; ++k) {
        const param_desc_t* d = &paper001_params.params[k];
        if (d->access == PARAM_RO || d->type != PARAM_F32) continue;
        bool skip = false;
        for (const char* u : unread) skip = skip || std::strcmp(u, d->name) == 0;
        if (skip) continue;
        p001_design_input_t in = base;
        const float x = d->def.f32 != 0.0f ? d->def.f32 * 1.1f : 0.5f * (d->min.f32 + d->max.f32);
        param_error_t e{};
        ASSERT_TRUE(params_write(&paper001_params, &in, d->id, f32v(std::fmin(x, d->max.f32)), false, &e))
            << d->name << ": " << e.text;
        auto got = std::make_unique<drive_config_storage_t>();
        if (design(in, got.get(), &why)) {
            EXPECT_NE(std::memcmp(got.get(), ref.get(), sizeof(paper001_config_t)), 0) << d->name << " not read";
        } else {
            EXPECT_FALSE(why.empty()) << d->name;
        }
    }
}

// ---- the board's table against the node's defaults, the DBC's value table --

TEST(Params, BoardDefaultsAreTodaysNode)
{
    can_tx_config_t c{};
    can_tx_defaults(&c, 0, 1000);  // at 1 kHz a period's samples are its ms
    for (const param_table_t* t : kBoardTables) {
        board_params_t b{};
        param_error_t e{};
        ASSERT_TRUE(params_set_defaults(t, &b, &e));
        EXPECT_EQ(b.can_node, 0u) << t->name;
        for (uint32_t m = 0; m < BOARD_PARAMS_TLM_COUNT; ++m) {
            EXPECT_EQ(b.tlm_period_ms[m], c.period_ticks[m]) << t->name << " message " << m;
        }
    }
    board_params_t b{};
    ASSERT_TRUE(params_set_defaults(&board_params_vesc6, &b, nullptr));
    EXPECT_EQ(b.dead_time_s, 500e-9);
    ASSERT_TRUE(params_set_defaults(&board_params_odrive36, &b, nullptr));
    EXPECT_EQ(b.dead_time_s, 119e-9);
    static_assert(BOARD_PARAMS_TLM_COUNT == CAN_TLM_COUNT, "a period per telemetry message");
}

TEST(Params, StatusNamesAreTheDbcs)
{
    std::ifstream f(src("tools/can/drive.dbc"));
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string dbc = ss.str();
    std::smatch m;
    ASSERT_TRUE(std::regex_search(dbc, m, std::regex("BO_ (\\d+) ParamReply: 8 DRIVE")));
    const std::string reply = m[1];
    ASSERT_TRUE(std::regex_search(dbc, m, std::regex("VAL_ " + reply + " Status ([^;]*);")));
    std::string want;
    for (int s = PARAM_OK; s <= PARAM_ERR_BUSY; ++s) {
        want += std::to_string(s) + " \"" + params_status_name(static_cast<param_status_t>(s)) + "\" ";
    }
    EXPECT_EQ(m[1].str(), want);
    EXPECT_STREQ(params_status_name(static_cast<param_status_t>(PARAM_ERR_BUSY + 1)), "unknown_status");
    EXPECT_STREQ(params_type_name(PARAM_ENUM), "enum");
    EXPECT_STREQ(params_access_name(PARAM_DISABLED), "disabled");
}

}  // namespace

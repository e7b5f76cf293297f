// hal.AppParams.*: the flashable image's parameters
// (hal/backends/stm32f405/app_params.h) on the host: paper 001's drive and
// design, the VESC 6's board table, the store on a simulated flash
// (tests/firmware/sim_flash.h). The control interrupt's part and the main
// loop's are called in turn as the board interleaves them: a request is
// taken by the interrupt and answered only after the main loop served it,
// a design is handed to the interrupt and the main loop waits for it, a
// save turns the bridges' outputs off around the flash writes, and a
// record that no longer designs leaves the drive on the image's values and
// not ready.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "sim_flash.h"

extern "C" {
#include "app_params.h"
#include "config/generated/board_params.h"
extern const drive_design_ops_t paper001_design_ops;
}

namespace {

constexpr uint16_t kR = 0x0101;         // paper 001's R_ohm
constexpr uint16_t kIMax = 0x0201;      // i_max_A
constexpr uint16_t kITrip = 0x0202;     // i_trip_A
constexpr uint16_t kDeadTime = 0x0020;  // the board's dead_time_s
constexpr uint16_t kTlmPosition = 0x0011;
constexpr uint32_t kControlHz = 10000;

uint32_t f32(float v)
{
    uint32_t u;
    std::memcpy(&u, &v, 4);
    return u;
}

struct Image {
    SimFlash flash{4096};
    drive_storage_t storage{};
    drive_t drive{};
    can_node_t node{};
    std::unique_ptr<app_params_t> p = std::make_unique<app_params_t>();
    std::vector<std::string> log;  // the hooks' calls, in order
    const char* board_refusal = nullptr;
    uint32_t tick = 0;
    bool interrupt_in_wait = true;  // the wait hook runs the interrupt's part

    static const char* board_apply(void* ctx, const board_params_t* b, uint32_t counts)
    {
        auto* im = static_cast<Image*>(ctx);
        im->log.push_back("board " + std::to_string(b->can_node) + " " + std::to_string(counts));
        return im->board_refusal;
    }
    static void pause(void* ctx, bool on)
    {
        auto* im = static_cast<Image*>(ctx);
        im->log.push_back(on ? "pause" : "resume");
        // the store writes only between the two: the board's flash refuses
        // while the bridges' outputs are on (hal/backends/stm32f405/flash.h)
        im->flash.refuse = !on;
    }
    static void wait(void* ctx)
    {
        auto* im = static_cast<Image*>(ctx);
        if (im->interrupt_in_wait) im->control();
    }
    bool start(const std::vector<app_param_value_t>& values, param_error_t* err)
    {
        const drive_ops_t* ops = drive_find("paper001");
        if (ops == nullptr || !drive_bind(&drive, ops, &storage)) return false;
        const app_params_hooks_t hooks = {&Image::board_apply, &Image::pause, &Image::wait, this};
        flash.refuse = true;  // the outputs on, as the interrupt runs
        fi = flash.interface();
        if (!app_params_init(p.get(), &paper001_design_ops, &board_params_vesc6, &drive, &node, &fi, &hooks, err)) {
            return false;
        }
        const bool ok = app_params_start(p.get(), values.data(), static_cast<uint32_t>(values.size()), kControlHz, err);
        p->running = true;
        // paper 001's drive starts enabled, holding at rest: a host
        // disables it before it changes the motor's parameters
        drive_cmd_t off{};
        off.kind = DRIVE_CMD_ENABLE;
        off.enable = false;
        (void)drive_command(&drive, &off);
        return ok;
    }
    // one control sample's part of the parameters (after the node's receive)
    void control() { app_params_control(p.get(), ++tick); }
    // a ParamRequest frame as the interrupt receives it
    can_reject_t receive(uint8_t op, uint8_t seq, uint16_t id, uint32_t value)
    {
        can_frame_t f{};
        f.id = 0x280u + node.tx.cfg.node;
        f.dlc = 8;
        f.data[0] = op;
        f.data[1] = seq;
        f.data[2] = static_cast<uint8_t>(id);
        f.data[3] = static_cast<uint8_t>(id >> 8);
        for (int k = 0; k < 4; ++k) f.data[4 + k] = static_cast<uint8_t>(value >> (8 * k));
        return can_node_receive(&node, tick, &f, &can_node_apply_drive, &drive);
    }
    struct Reply {
        bool some = false;
        uint8_t op = 0, status = 0, seq = 0;
        uint16_t id = 0;
        uint32_t value = 0;
    };
    // the ParamReply queued, if any (telemetry frames skipped)
    Reply reply()
    {
        Reply r;
        can_frame_t f{};
        while (can_node_peek(&node, &f)) {
            can_node_pop(&node);
            if (f.id != 0x180u + node.tx.cfg.node) continue;
            r.some = true;
            r.op = f.data[0] & 0x0F;
            r.status = f.data[0] >> 4;
            r.seq = f.data[1];
            r.id = static_cast<uint16_t>(f.data[2] | (f.data[3] << 8));
            r.value = static_cast<uint32_t>(f.data[4]) | (static_cast<uint32_t>(f.data[5]) << 8) |
                      (static_cast<uint32_t>(f.data[6]) << 16) | (static_cast<uint32_t>(f.data[7]) << 24);
        }
        return r;
    }
    // a request through the interrupt, the main loop, the interrupt again
    Reply request(uint8_t op, uint16_t id = 0, uint32_t value = 0)
    {
        (void)reply();  // drop earlier frames
        EXPECT_EQ(receive(op, ++seq, id, value), CAN_REJECT_NONE);
        app_params_poll(p.get());
        control();
        Reply r = reply();
        EXPECT_TRUE(r.some) << "no ParamReply";
        EXPECT_EQ(r.seq, seq);
        return r;
    }
    flash_if_t fi{};
    uint8_t seq = 0;
};

float as_f32(uint32_t u)
{
    float v;
    std::memcpy(&v, &u, 4);
    return v;
}

// The drive's configuration as the host designs it from the same
// parameters (the design input the service holds).
std::vector<uint8_t> host_design(const app_params_t& p)
{
    auto cfg = std::make_unique<drive_config_storage_t>();
    std::memset(cfg.get(), 0, sizeof *cfg);
    char err[128] = {0};
    EXPECT_TRUE(paper001_design_ops.design(p.input.b, cfg.get(), err, sizeof err)) << err;
    const auto* b = reinterpret_cast<const uint8_t*>(cfg.get());
    return std::vector<uint8_t>(b, b + paper001_design_ops.config_bytes);
}

std::vector<uint8_t> next_config(const app_params_t& p)
{
    const auto* b = reinterpret_cast<const uint8_t*>(&p.next);
    return std::vector<uint8_t>(b, b + paper001_design_ops.config_bytes);
}

}  // namespace

TEST(AppParams, StartDesignsFromTheImageValuesAndTheBoardPartIsSet)
{
    Image im;
    param_error_t err{};
    // the image's values over the table's defaults (a board's scenario: R 0.3 ohm)
    ASSERT_TRUE(im.start({{kR, f32(0.3f)}}, &err)) << err.text;
    EXPECT_TRUE(app_params_may_enable(im.p.get()));
    EXPECT_FALSE(im.p->start_refused);
    EXPECT_EQ(im.p->store.source, CONFIG_SOURCE_DEFAULTS);       // a new board: nothing stored
    EXPECT_EQ(param_service_config_source(&im.p->service), 3u);  // the heartbeat's defaults_empty
    EXPECT_EQ(next_config(*im.p), host_design(*im.p));
    ASSERT_EQ(im.log.size(), 1u);
    EXPECT_EQ(im.log[0], "board 0 0");  // node 0, no encoder (paper 001 reads none)
    const Image::Reply r = im.request(PARAM_OP_READ, kR);
    EXPECT_EQ(r.status, PARAM_OK);
    EXPECT_EQ(r.value, f32(0.3f));
}

TEST(AppParams, ARequestIsAnsweredOnlyAfterTheMainLoopServedIt)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    (void)im.reply();
    ASSERT_EQ(im.receive(PARAM_OP_READ, 7, kR, 0), CAN_REJECT_NONE);
    im.control();
    EXPECT_FALSE(im.reply().some) << "answered in the interrupt, before the main loop served it";
    EXPECT_FALSE(app_params_may_enable(im.p.get())) << "CmdEnable must wait for the request in flight";
    // a second request meanwhile: busy, at once
    ASSERT_EQ(im.receive(PARAM_OP_READ, 8, kR, 0), CAN_REJECT_NONE);
    Image::Reply busy = im.reply();
    ASSERT_TRUE(busy.some);
    EXPECT_EQ(busy.seq, 8);
    EXPECT_EQ(busy.status, PARAM_ERR_BUSY);
    app_params_poll(im.p.get());
    EXPECT_FALSE(im.reply().some) << "the main loop queued a frame: only the interrupt may";
    im.control();
    const Image::Reply r = im.reply();
    ASSERT_TRUE(r.some);
    EXPECT_EQ(r.seq, 7);
    EXPECT_EQ(r.status, PARAM_OK);
    EXPECT_EQ(as_f32(r.value), 0.225f);
    EXPECT_TRUE(app_params_may_enable(im.p.get()));
}

TEST(AppParams, AWriteIsDesignedInTheMainLoopAndTakenByTheInterrupt)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    const std::vector<uint8_t> before = next_config(*im.p);
    const Image::Reply r = im.request(PARAM_OP_WRITE, kR, f32(0.4f));
    EXPECT_EQ(r.status, PARAM_OK);
    EXPECT_NE(next_config(*im.p), before);
    EXPECT_EQ(next_config(*im.p), host_design(*im.p));
    EXPECT_EQ(im.log.back(), "board 0 0");  // the interrupt took it: the board's part set again
    EXPECT_EQ(im.p->cfg_slot, APP_SLOT_IDLE);
    drive_status_t st{};
    drive_status(&im.drive, &st);
    EXPECT_FALSE(st.enabled);
    EXPECT_TRUE(app_params_may_enable(im.p.get()));
    // without the interrupt the wait ends, bounded, and the write is refused
    im.interrupt_in_wait = false;
    const Image::Reply stuck = im.request(PARAM_OP_WRITE, kR, f32(0.5f));
    EXPECT_EQ(stuck.status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_FALSE(app_params_may_enable(im.p.get()));
}

TEST(AppParams, ADesignRefusedKeepsTheValueAndTheDriveNotReady)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    const size_t takes = im.log.size();  // the interrupt's takes call the board's hook
    // a current limit above the trip level: the design refuses it
    Image::Reply r = im.request(PARAM_OP_WRITE, kIMax, f32(20.0f));
    EXPECT_EQ(r.status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_FALSE(app_params_may_enable(im.p.get()));
    EXPECT_EQ(im.request(PARAM_OP_READ, kIMax).value, f32(20.0f));
    EXPECT_EQ(im.log.size(), takes) << "the refused design reached the interrupt";
    EXPECT_EQ(im.request(PARAM_OP_SAVE).status, PARAM_ERR_DESIGN_REFUSED);
    // the second write of the change designs
    r = im.request(PARAM_OP_WRITE, kITrip, f32(30.0f));
    EXPECT_EQ(r.status, PARAM_OK);
    EXPECT_TRUE(app_params_may_enable(im.p.get()));
}

TEST(AppParams, SaveRunsBetweenPauseAndResumeAndARestartKeepsTheValue)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    ASSERT_EQ(im.request(PARAM_OP_WRITE, kR, f32(0.35f)).status, PARAM_OK);
    ASSERT_EQ(im.request(PARAM_OP_WRITE, kTlmPosition, 50u).status, PARAM_OK);
    im.log.clear();
    const uint64_t ops_before = im.flash.ops;
    ASSERT_EQ(im.request(PARAM_OP_SAVE).status, PARAM_OK);
    ASSERT_EQ(im.log.size(), 2u);
    EXPECT_EQ(im.log[0], "pause");
    EXPECT_EQ(im.log[1], "resume");
    EXPECT_GT(im.flash.ops, ops_before);
    EXPECT_TRUE(im.flash.refuse) << "the outputs were not turned back on";
    // the power goes; the same flash at the next start
    Image again;
    again.flash = im.flash;
    ASSERT_TRUE(again.start({}, &err)) << err.text;
    EXPECT_EQ(again.p->store.source, CONFIG_SOURCE_RECORD);
    EXPECT_EQ(param_service_config_source(&again.p->service), 1u);  // the heartbeat's record
    EXPECT_EQ(again.request(PARAM_OP_READ, kR).value, f32(0.35f));
    EXPECT_EQ(again.request(PARAM_OP_READ, kTlmPosition).value, 50u);
    EXPECT_EQ(next_config(*again.p), host_design(*again.p));
    EXPECT_EQ(again.node.tx.cfg.period_ticks[1], 500u);  // 50 ms at 10 kHz
    // defaults: the image's values (not the store's), not saved
    ASSERT_EQ(again.request(PARAM_OP_DEFAULTS).status, PARAM_OK);
    EXPECT_EQ(as_f32(again.request(PARAM_OP_READ, kR).value), 0.225f);
}

TEST(AppParams, ABoardParameterChangesLiveWithoutADesign)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    drive_cmd_t on{};
    on.kind = DRIVE_CMD_ENABLE;
    on.enable = true;
    ASSERT_EQ(drive_command(&im.drive, &on), DRIVE_REFUSE_NONE);
    const std::vector<uint8_t> before = next_config(*im.p);
    // a telemetry period while enabled: live
    EXPECT_EQ(im.request(PARAM_OP_WRITE, kTlmPosition, 20u).status, PARAM_OK);
    EXPECT_EQ(im.node.tx.cfg.period_ticks[1], 200u);
    drive_status_t st{};
    drive_status(&im.drive, &st);
    EXPECT_TRUE(st.enabled) << "a live parameter re-initialised the drive";
    // the dead time only while disabled; a save neither
    EXPECT_EQ(im.request(PARAM_OP_WRITE, kDeadTime, f32(300e-9f)).status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_EQ(im.request(PARAM_OP_SAVE).status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_EQ(next_config(*im.p), before);
}

TEST(AppParams, TheBoardRefusingItsPartIsADesignRefusal)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    im.board_refusal = "the PWM frequency or dead time cannot be set";
    const Image::Reply r = im.request(PARAM_OP_WRITE, kDeadTime, f32(1.9e-6f));
    EXPECT_EQ(r.status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_FALSE(app_params_may_enable(im.p.get()));
    EXPECT_EQ(std::string(im.p->service.last_error.text), im.board_refusal);
}

TEST(AppParams, AStoredRecordThatNoLongerDesignsLeavesTheImageValuesRunningAndNotReady)
{
    Image im;
    param_error_t err{};
    ASSERT_TRUE(im.start({}, &err)) << err.text;
    const std::vector<uint8_t> base = next_config(*im.p);
    // a record whose values do not design (as a firmware whose design
    // rules changed would find one): i_max above i_trip
    param_service_t& s = im.p->service;
    std::vector<config_entry_t> values(s.defaults, s.defaults + s.schema.n_entries);
    for (auto& e : values) {
        if (e.id == kIMax) e.value = f32(20.0f);
    }
    im.flash.refuse = false;
    ASSERT_TRUE(config_store_save(&im.p->store, values.data())) << config_store_last_error(&im.p->store);
    Image again;
    again.flash = im.flash;
    ASSERT_TRUE(again.start({}, &err)) << err.text;
    EXPECT_TRUE(again.p->start_refused);
    EXPECT_EQ(again.p->start_error.status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_NE(std::string(again.p->start_error.text), "");
    EXPECT_FALSE(app_params_may_enable(again.p.get()));
    EXPECT_EQ(next_config(*again.p), base) << "the drive does not run the image's values";
    // the stored value is kept for the host to see and mend
    EXPECT_EQ(again.request(PARAM_OP_READ, kIMax).value, f32(20.0f));
    ASSERT_EQ(again.request(PARAM_OP_WRITE, kIMax, f32(8.0f)).status, PARAM_OK);
    EXPECT_TRUE(app_params_may_enable(again.p.get()));
    EXPECT_FALSE(again.p->start_refused);
}

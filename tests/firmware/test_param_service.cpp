// firmware.ParamService.*: the parameters of a running board served by id
// (firmware/config/param_service.h) over paper 001's and the VESC 6's
// generated tables, a simulated flash (sim_flash.h) and a hook that
// designs paper 001 from its design input (design/paper001_design.h, the
// host's design code): every op of ParamRequest answered, each refusal
// named once, a saved value read back after a restart on the same flash
// and designed, a refused design keeping the drive not ready and the save
// refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "sim_flash.h"

extern "C" {
#include "config/board_params.h"
#include "config/generated/board_params.h"
#include "config/param_service.h"
#include "design/paper001_design.h"
#include "drives/paper001/generated/paper001_params.h"
}

namespace {

// What the application does on a change: paper 001 designed again from
// its design input (the board's parameters need nothing here).
struct Board {
    board_params_t board{};
    p001_design_input_t input{};
    paper001_config_t cfg{};
    int applies = 0;
    char err[160] = {0};
    bool refuse_next = false;  // a design that fails, whatever the input
};

bool apply(void* ctx, const param_table_t* t, uint16_t id, param_error_t* err)
{
    auto* b = static_cast<Board*>(ctx);
    ++b->applies;
    if (t == &board_params_vesc6) return true;
    p001_design_report_t rep{};
    if (b->refuse_next || !p001_design(&b->input, &b->cfg, &rep, b->err, sizeof(b->err))) {
        err->status = PARAM_ERR_DESIGN_REFUSED;
        err->id = id;
        err->text = b->refuse_next ? "refused on purpose" : b->err;
        return false;
    }
    return true;
}

struct Rig {
    SimFlash flash{4096};
    flash_if_t fi{};
    config_store_t store{};
    Board b;
    std::unique_ptr<param_service_t> s = std::make_unique<param_service_t>();

    explicit Rig(const SimFlash* from = nullptr)
    {
        if (from != nullptr) flash = *from;
        fi = flash.interface();
    }
    bool start(bool with_store = true)
    {
        param_error_t err{};
        if (!param_service_init(s.get(), &board_params_vesc6, &b.board, &paper001_params, &b.input,
                                with_store ? &store : nullptr, with_store ? &fi : nullptr, apply, &b, &err)) {
            ADD_FAILURE() << "init: " << err.text;
            return false;
        }
        uint32_t refused = 0;
        const bool ok = param_service_start(s.get(), false, &refused, &err);
        EXPECT_EQ(refused, 0u);
        return ok;
    }
    param_reply_t req(uint8_t op, uint16_t id = 0, uint32_t bits = 0, bool enabled = false, uint8_t seq = 7)
    {
        param_request_t r{};
        r.op = op;
        r.seq = seq;
        r.id = id;
        r.value.u32 = bits;
        param_reply_t out{};
        param_service_request(s.get(), &r, enabled, &out);
        EXPECT_EQ(out.seq, seq);
        EXPECT_EQ(out.op, op);
        return out;
    }
};

uint32_t bits(float x)
{
    param_value_t v;
    v.f32 = x;
    return v.u32;
}
float as_f(const param_reply_t& r) { return r.value.f32; }

TEST(ParamService, StartsOnTheDefaultsOfANewBoardAndDesignsThem)
{
    Rig r;
    ASSERT_TRUE(r.start());
    EXPECT_TRUE(param_service_ready(r.s.get()));
    EXPECT_EQ(r.b.applies, 1);
    EXPECT_EQ(r.store.source, CONFIG_SOURCE_DEFAULTS);
    EXPECT_EQ(r.store.defaults_reason, CONFIG_ERR_NO_RECORD);
    EXPECT_EQ(r.b.input.motor.R_ohm, 0.225);  // the table's exact default
    EXPECT_EQ(r.b.board.can_node, 0u);
    const param_reply_t rd = r.req(PARAM_OP_READ, PAPER001_PARAMS_R_OHM);
    EXPECT_EQ(rd.status, PARAM_OK);
    EXPECT_EQ(as_f(rd), 0.225f);
}

TEST(ParamService, AWrittenAndSavedValueOutlivesARestartAndIsDesigned)
{
    Rig r;
    ASSERT_TRUE(r.start());
    const double R0 = r.b.cfg.est.model.R_ohm;
    const param_reply_t w = r.req(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(0.3f));
    ASSERT_EQ(w.status, PARAM_OK);
    EXPECT_EQ(as_f(w), 0.3f);
    EXPECT_EQ(r.b.input.motor.R_ohm, static_cast<double>(0.3f));
    EXPECT_EQ(r.b.applies, 2);
    EXPECT_NE(r.b.cfg.est.model.R_ohm, R0);  // designed from it
    ASSERT_EQ(r.req(PARAM_OP_SAVE).status, PARAM_OK);
    EXPECT_EQ(r.store.saves, 1u);

    Rig again(&r.flash);  // the power cycled: a new service on the same flash
    ASSERT_TRUE(again.start());
    EXPECT_EQ(again.store.source, CONFIG_SOURCE_RECORD);
    EXPECT_EQ(as_f(again.req(PARAM_OP_READ, PAPER001_PARAMS_R_OHM)), 0.3f);
    EXPECT_EQ(again.b.input.motor.R_ohm, static_cast<double>(0.3f));
    EXPECT_EQ(std::memcmp(&again.b.cfg, &r.b.cfg, sizeof(r.b.cfg)), 0);  // the same design as before the cut
    // a value never written keeps the default's exact double
    EXPECT_EQ(again.b.input.motor.L_H, r.b.input.motor.L_H);
}

TEST(ParamService, EveryRefusalIsNamed)
{
    Rig r;
    ASSERT_TRUE(r.start());
    EXPECT_EQ(r.req(PARAM_OP_READ, 0x0FFF).status, PARAM_ERR_UNKNOWN_ID);
    EXPECT_EQ(r.req(PARAM_OP_WRITE, 0x0FFF, 0).status, PARAM_ERR_UNKNOWN_ID);
    EXPECT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_TS_S, bits(2e-4f)).status, PARAM_ERR_READ_ONLY);
    EXPECT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(1e3f)).status, PARAM_ERR_OUT_OF_RANGE);
    EXPECT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(NAN)).status, PARAM_ERR_BAD_VALUE);
    EXPECT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(0.3f), true).status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_EQ(r.req(PARAM_OP_SAVE, 0, 0, true).status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_EQ(r.req(PARAM_OP_DEFAULTS, 0, 0, true).status, PARAM_ERR_NOT_WHILE_ENABLED);
    EXPECT_EQ(r.req(9).status, PARAM_ERR_BAD_REQUEST);
    EXPECT_EQ(r.b.input.motor.R_ohm, 0.225);  // nothing of the refused written
    EXPECT_EQ(r.s->refused, 9u);
    // a live parameter may change while enabled
    EXPECT_EQ(r.req(PARAM_OP_WRITE, BOARD_PARAMS_TLM_VELOCITY_MS, 50u, true).status, PARAM_OK);
    EXPECT_EQ(r.b.board.tlm_period_ms[2], 50u);

    // the flash refuses (the driver sees the bridge enabled): store_failed, the record kept
    r.flash.refuse = true;
    const param_reply_t sv = r.req(PARAM_OP_SAVE);
    EXPECT_EQ(sv.status, PARAM_ERR_STORE_FAILED);
    EXPECT_EQ(r.s->last_error.status, PARAM_ERR_STORE_FAILED);
    EXPECT_EQ(r.store.saves, 0u);

    Rig none;
    ASSERT_TRUE(none.start(false));
    EXPECT_EQ(none.req(PARAM_OP_SAVE).status, PARAM_ERR_STORE_FAILED);
}

TEST(ParamService, ARefusedDesignKeepsTheValueAndTheDriveNotReady)
{
    Rig r;
    ASSERT_TRUE(r.start());
    // i_max above the trip current: in range for each, refused by the design
    const param_reply_t w =
        r.req(PARAM_OP_WRITE, PAPER001_PARAMS_I_MAX_A, bits(static_cast<float>(r.b.input.i_trip_A * 1.5)));
    EXPECT_EQ(w.status, PARAM_ERR_DESIGN_REFUSED) << r.s->last_error.text;
    EXPECT_EQ(r.s->last_error.id, PAPER001_PARAMS_I_MAX_A);
    EXPECT_NE(std::strlen(r.s->last_error.text), 0u);
    EXPECT_FALSE(param_service_ready(r.s.get()));
    EXPECT_EQ(r.req(PARAM_OP_SAVE).status, PARAM_ERR_DESIGN_REFUSED);  // nothing that does not design is saved
    EXPECT_EQ(r.store.saves, 0u);
    // the second write of the pair designs again
    ASSERT_EQ(
        r.req(PARAM_OP_WRITE, PAPER001_PARAMS_I_TRIP_A, bits(static_cast<float>(r.b.input.i_trip_A * 2.0))).status,
        PARAM_OK)
        << r.s->last_error.text;
    EXPECT_TRUE(param_service_ready(r.s.get()));
    EXPECT_EQ(r.req(PARAM_OP_SAVE).status, PARAM_OK);
}

TEST(ParamService, ListWalksTheBoardsThenTheDrivesParameters)
{
    Rig r;
    ASSERT_TRUE(r.start());
    std::vector<uint16_t> ids;
    uint16_t at = 0;
    for (int guard = 0; guard < 200; ++guard) {
        const param_reply_t l = r.req(PARAM_OP_LIST, at);
        if (l.status != PARAM_OK) {
            EXPECT_EQ(l.status, PARAM_ERR_UNKNOWN_ID);
            EXPECT_EQ(l.id, PARAM_ID_NONE);
            break;
        }
        ids.push_back(l.id);
        param_reply_t rd = r.req(PARAM_OP_READ, l.id);
        EXPECT_EQ(rd.value.u32, l.value.u32) << std::hex << l.id;
        at = static_cast<uint16_t>(l.id + 1u);
    }
    ASSERT_EQ(ids.size(), BOARD_PARAMS_COUNT + PAPER001_PARAMS_COUNT);
    for (size_t k = 1; k < ids.size(); ++k) EXPECT_LT(ids[k - 1], ids[k]);
}

TEST(ParamService, DefaultsRestoreTheBaseAndDesignIt)
{
    Rig r;
    ASSERT_TRUE(r.start());
    const paper001_config_t cfg0 = r.b.cfg;
    ASSERT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_L_H, bits(5e-3f)).status, PARAM_OK);
    ASSERT_EQ(r.req(PARAM_OP_WRITE, BOARD_PARAMS_CAN_NODE, 3u).status, PARAM_OK);
    ASSERT_EQ(r.req(PARAM_OP_DEFAULTS).status, PARAM_OK);
    EXPECT_EQ(r.b.input.motor.L_H, 3.8e-3);  // the default's exact double again
    EXPECT_EQ(r.b.board.can_node, 0u);
    EXPECT_EQ(std::memcmp(&r.b.cfg, &cfg0, sizeof(cfg0)), 0);
}

TEST(ParamService, KeptTargetsAreTheBaseAndKeepTheirExactValues)
{
    Rig r;
    p001_design_defaults(&r.b.input);
    param_error_t err{};
    ASSERT_TRUE(params_set_defaults(&paper001_params, &r.b.input, &err));
    ASSERT_TRUE(params_set_defaults(&board_params_vesc6, &r.b.board, &err));
    r.b.input.motor.R_ohm = 0.2345678901234;  // a scenario's value, not a float32
    ASSERT_TRUE(param_service_init(r.s.get(), &board_params_vesc6, &r.b.board, &paper001_params, &r.b.input, &r.store,
                                   &r.fi, apply, &r.b, &err));
    ASSERT_TRUE(param_service_start(r.s.get(), true, nullptr, &err));
    EXPECT_EQ(r.b.input.motor.R_ohm, 0.2345678901234);
    ASSERT_EQ(r.req(PARAM_OP_WRITE, PAPER001_PARAMS_J_KGM2, bits(0.015f)).status, PARAM_OK) << r.s->last_error.text;
    ASSERT_EQ(r.req(PARAM_OP_SAVE).status, PARAM_OK);
    Rig again(&r.flash);
    p001_design_defaults(&again.b.input);
    ASSERT_TRUE(params_set_defaults(&paper001_params, &again.b.input, &err));
    ASSERT_TRUE(params_set_defaults(&board_params_vesc6, &again.b.board, &err));
    again.b.input.motor.R_ohm = 0.2345678901234;
    ASSERT_TRUE(param_service_init(again.s.get(), &board_params_vesc6, &again.b.board, &paper001_params, &again.b.input,
                                   &again.store, &again.fi, apply, &again.b, &err));
    ASSERT_TRUE(param_service_start(again.s.get(), true, nullptr, &err));
    EXPECT_EQ(again.b.input.motor.R_ohm, 0.2345678901234);  // the record's equal bits leave it exact
    EXPECT_EQ(again.b.input.motor.J_kgm2, static_cast<double>(0.015f));
}

}  // namespace

// Paper 001's drive (firmware/drives/paper001/paper001_drive.h) behind the
// drive interface (drives/drive.h): a refused configuration names its
// first offending field (config_problem), and init refuses exactly what
// config_problem names.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "drives/registry.h"
#include "math/mc_convert.h"
#include "p001_fixture.h"

namespace {

paper001_config_t designed()
{
    p001_design_input_t in = fwtest::p001_input();
    paper001_config_t cfg{};
    p001_design_report_t rep;
    char err[160];
    EXPECT_TRUE(p001_design(&in, &cfg, &rep, err, sizeof err)) << err;
    return cfg;
}

}  // namespace

// The designed configuration has no problem; each broken field is named
// first in the problem (a literal, "field: ..."), through the interface's
// operation too, and init refuses it: FAULT, BAD_INPUT latched.
// Broken once: the check of limits.i_trip_A left out of
// paper001_config_problem (its case failed: no problem named).
TEST(Paper001Drive, ConfigProblemNamesTheFirstOffendingField)
{
    const drive_ops_t* ops = drive_find("paper001");
    ASSERT_NE(ops, nullptr);
    ASSERT_NE(ops->config_problem, nullptr);
    const paper001_config_t good = designed();
    EXPECT_EQ(paper001_config_problem(&good), nullptr) << paper001_config_problem(&good);
    EXPECT_EQ(ops->config_problem(&good), nullptr);
    static paper001_drive_t d;
    ASSERT_TRUE(paper001_drive_init(&d, &good));

    struct Case {
        const char* field;
        std::function<void(paper001_config_t*)> breaks;
    };
    const Case cases[] = {
        {"n_phases", [](paper001_config_t* c) { c->n_phases = 4u; }},
        {"model.L_H", [](paper001_config_t* c) { c->model.L_H = MC_ZERO; }},
        {"limits.i_trip_A", [](paper001_config_t* c) { c->limits.i_trip_A = MC_ZERO; }},
        {"flux.rho_gain", [](paper001_config_t* c) { c->flux.rho_gain = MC_ZERO; }},
        {"sup.blend_decay", [](paper001_config_t* c) { c->sup.blend_decay = MC_ONE; }},
        {"fit.decim", [](paper001_config_t* c) { c->fit.decim = 0; }},
        {"compute_delay", [](paper001_config_t* c) { c->compute_delay = mc_from_double(1.5); }},
        {"emf.pos.n_p",
         [](paper001_config_t* c) {
             c->estimator = P001_ESTIMATOR_BACK_EMF;
             c->emf.pos.n_p = c->model.n_p + 1;
         }},
        {"profile", [](paper001_config_t* c) { c->profile.t_tick[1] = c->profile.t_tick[0]; }},
        {"deadtime", [](paper001_config_t* c) { c->deadtime.k_bus = mc_from_double(-1.0); }},
    };
    for (const Case& k : cases) {
        paper001_config_t bad = good;
        k.breaks(&bad);
        const char* why = paper001_config_problem(&bad);
        ASSERT_NE(why, nullptr) << k.field;
        EXPECT_EQ(std::string(why).rfind(std::string(k.field) + ":", 0), 0u) << k.field << ": " << why;
        EXPECT_EQ(ops->config_problem(&bad), why) << k.field;
        EXPECT_FALSE(paper001_drive_init(&d, &bad)) << k.field;
        EXPECT_EQ(d.sup.state, SUP_STATE_FAULT) << k.field;
        EXPECT_EQ(d.sup.fault, DRIVE_FAULT_BAD_INPUT) << k.field;
    }
    // the first offending field when two are: in the order of the checks
    paper001_config_t two = good;
    two.limits.i_trip_A = MC_ZERO;
    two.fit.decim = 0;
    EXPECT_EQ(std::string(paper001_config_problem(&two)).rfind("limits.i_trip_A:", 0), 0u);
}

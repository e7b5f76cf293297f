// Drive-level behaviour: configuration checks, safe state, limits, switching.
#include <gtest/gtest.h>

#include <cmath>

#include "design/drive_design.h"
#include "math/mc_convert.h"

namespace {
drive_design_input_t paper_input()
{
    drive_design_input_t in;
    drive_design_defaults(&in);
    in.motor = {9e-3, 3.01, 0.27, 3.18e-4, 2.37e-3, 50};
    in.n_segments = 2;
    in.segments[0] = {0.0, 2.0, 18.0};
    in.segments[1] = {2.0, 2.0, 0.0};
    return in;
}
double D(mc_t x) { return mc_to_double(x); }
// the paper-000 rig and trajectory, designed and initialised
bool init_paper_drive(drive_t *d)
{
    drive_design_input_t in = paper_input();
    drive_config_t cfg;
    char err[160];
    return drive_design(&in, &cfg, err, sizeof err) && drive_init(d, &cfg);
}

drive_telemetry_t tlm_of(const drive_t &d)
{
    drive_telemetry_t t;
    drive_get_telemetry(&d, &t);
    return t;
}
mc_t M(double x) { return mc_from_double(x); }
}  // namespace

TEST(DriveDesign, RejectsNonPhysicalInputNamingTheField)
{
    char err[160];
    drive_config_t cfg;
    drive_design_input_t in = paper_input();
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err)) << err;
    in.motor.L_H = -1.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("motor.L_H"), std::string::npos) << err;
    in = paper_input();
    in.ts_s = 0.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("Ts_s"), std::string::npos) << err;
    in = paper_input();
    in.segments[1].duration_s = -2.0;
    EXPECT_FALSE(drive_design(&in, &cfg, err, sizeof err));
    EXPECT_NE(std::string(err).find("duration_s"), std::string::npos) << err;
}

TEST(DriveDesign, GainsMeetTheSlidingModeConditions)
{
    drive_design_input_t in = paper_input();
    drive_config_t cfg;
    char err[160];
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err)) << err;
    const double L = 9e-3, K = 0.27, J = 3.18e-4, fv = 2.37e-3, Ts = 1e-4;
    // observer: alpha > Pi_d with Pi_d = (K/L)(a_max + n_p w_max dw_max), (26)
    const double a_max = 7.5132 * 18.0 / 4.0, w_max = 2.1875 * 9.0;
    const double Pi_d = K / L * (a_max + 50 * w_max * in.bound_delta_omega_rad_s);
    const double alpha = D(cfg.emf.alpha_V) / (L * Ts);
    EXPECT_GT(alpha, Pi_d);
    // twisting (22)/(57): lambda_m > C0, lambda_M > lambda_m + 2 C0 (in rad/s^3)
    const double k = D(cfg.k_surface_per_s);
    const double C0 = std::fabs(k / J - fv / (J * J)) * in.bound_load_Nm + in.bound_load_rate_Nm_s / J +
                      K / (J * L) * in.bound_model_error_V;
    const double lm = D(cfg.pos_ctrl.lambda_m) * K / (J * L), lM = D(cfg.pos_ctrl.lambda_M) * K / (J * L);
    EXPECT_GT(lm, C0);
    EXPECT_GT(lM, lm + 2 * C0);
}

TEST(Drive, BadConfigGoesToSafeState)
{
    drive_design_input_t in = paper_input();
    drive_config_t cfg;
    char err[160];
    ASSERT_TRUE(drive_design(&in, &cfg, err, sizeof err));
    cfg.i_trip_A = M(1.0);  // below i_max: inconsistent
    drive_t d;
    EXPECT_FALSE(drive_init(&d, &cfg));
    mc_t va = M(5), vb = M(5);
    EXPECT_FALSE(drive_step(&d, M(0), M(0), &va, &vb));
    EXPECT_EQ(D(va), 0.0);
    EXPECT_EQ(D(vb), 0.0);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_FAULT);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_BAD_INPUT);
}

TEST(Drive, OvercurrentTripsAndStaysSafe)
{
    drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    mc_t va, vb;
    EXPECT_TRUE(drive_step(&d, M(0.1), M(0.0), &va, &vb));
    EXPECT_GT(std::fabs(D(va)) + std::fabs(D(vb)), 1.0);  // open loop holds the rotor
    EXPECT_FALSE(drive_step(&d, M(7.0), M(0.0), &va, &vb));
    EXPECT_EQ(D(va), 0.0);
    EXPECT_EQ(tlm_of(d).fault, DRIVE_FAULT_OVERCURRENT);
    for (int k = 0; k < 10; ++k) {  // latched until drive_init
        EXPECT_FALSE(drive_step(&d, M(0.0), M(0.0), &va, &vb));
        EXPECT_EQ(D(va), 0.0);
        EXPECT_EQ(D(vb), 0.0);
    }
}

TEST(Drive, OpenLoopAtStandstillFollowsEq68AndPhaseVoltagesStayWithinVmax)
{
    drive_t d;
    ASSERT_TRUE(init_paper_drive(&d));
    mc_t va, vb;
    ASSERT_TRUE(drive_step(&d, M(0), M(0), &va, &vb));
    // theta_r = 0 at t = 0: v along phase a with magnitude R I_max (68)
    EXPECT_NEAR(D(va), 3.01 * 3.0, 1e-3);
    EXPECT_NEAR(D(vb), 0.0, 1e-3);
    EXPECT_EQ(tlm_of(d).mode, DRIVE_MODE_OPEN_LOOP);
    // absurd currents just below the trip: whatever the law asks, |v| <= V_max
    for (int k = 0; k < 200; ++k) {
        const double ia = 5.9 * std::sin(0.3 * k), ib = -5.9 * std::cos(0.7 * k);
        drive_step(&d, M(ia), M(ib), &va, &vb);
        EXPECT_LE(std::fabs(D(va)), 30.0 + 1e-4);
        EXPECT_LE(std::fabs(D(vb)), 30.0 + 1e-4);
    }
}

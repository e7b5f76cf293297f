// Faults injected into the simulated rig (issue 10; ctest label "fault"):
// for each, the paper-000 drive on paper000_experiment.toml detects it
// within the time its criterion states (docs/faults.md), reacts as
// configured, switches without a voltage step beyond the stated bounds,
// freezes a flight-recorder snapshot that shows the fault, and ends with
// its currents within the limit and its state finite.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hal/hal.h"
#include "hal_sw_plant.h"
#include "mc_convert.h"
#include "host_drives/paper000_host.h"
#include "host_drives/paper001_host.h"
#include "scenario/rig.h"
#include "scenario/scenario.h"

namespace {

constexpr double kInject = 1.5;  // s: closed loop at ~9 rad/s on the way back
// Bounds the drive states (docs/faults.md, "Voltage steps"): a switch
// between laws (open/closed loop, a re-lock) is bumpless (in the (f-g)
// frame the applied voltage is continuous), so at a switch a phase
// voltage changes by at most 0.5 V more than it did in the sample before
// (the voltage vector turns with the rotor: at 9 rad/s a 14 V vector moves
// its phase voltages by 0.6 V a sample anyway); the open-loop start at rest
// steps by R I (6.02 V at the design's 2 A, 9.03 V at I_max), which the R/L
// measurement needs; entering the safe state drops to 0 V at once.
constexpr double kSwitchStepMax_V = 0.5;

struct Period {
    double t;
    int state;
    int fault;
    double va, vb;      // commanded
    double ia, ib;      // true plant currents
    double theta;       // true rotor angle [rad]
    int relocks;        // the drive's re-locks so far
    std::uint32_t tick; // the drive's tick after the sample
};

// Alters a sample before the drive sees it (the drive as it is then, the
// sample): a glitch or a status bit the injector has no key for.
using Tamper = std::function<void(const paper000_drive_t&, hal_sample_t*)>;

struct Ctx {
    paper000_drive_t* drive;
    const mcsim::PmPlant* plant;
    std::vector<Period> log;
    Tamper tamper;
};

void control(void* p, const hal_sample_t* in, hal_command_t* out)
{
    Ctx* c = static_cast<Ctx*>(p);
    hal_sample_t s = *in;
    if (c->tamper) c->tamper(*c->drive, &s);
    if (!paper000_drive_step(c->drive, &s, out)) hal_safe_state();
}

void monitor(void* p, const hal_sw_plant_period_t* q)
{
    Ctx* c = static_cast<Ctx*>(p);
    c->log.push_back({q->t_s, static_cast<int>(c->drive->sup.state), static_cast<int>(c->drive->sup.fault),
                      q->v_a_cmd_V, q->v_b_cmd_V, c->plant->i_a_A(), c->plant->i_b_A(), c->plant->theta_rad(),
                      static_cast<int>(c->drive->relocks), c->drive->tick});
}

struct Result {
    std::vector<Period> log;
    paper000_drive_t drive;
    mcsim::Scenario sc;
    double ts;
    double t_first() const
    {
        const flight_recorder_t* r = paper000_drive_flight_recorder(&drive);
        return r->frozen ? sc.t_start_s() + r->fault_tick * ts : -1.0;
    }
};

Result run(mcsim::Scenario sc, fault_reaction_t los_reaction = FAULT_REACT_SAFE, Tamper tamper = nullptr)
{
    Result r;
    mcsim::design_and_init_drive(sc, &r.drive);
    r.drive.cfg.prot.reaction[DRIVE_FAULT_LOSS_OF_SYNC] = static_cast<std::uint8_t>(los_reaction);
    r.sc = sc;
    r.ts = sc.ts_s;
    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    mcsim::FaultInjector inj(sc.faults, sc.seed);
    hal_sw_plant_set_faults(&inj);
    Ctx ctx{&r.drive, &rig.plant, {}, std::move(tamper)};
    hal_sw_plant_set_monitor(monitor, &ctx);
    EXPECT_TRUE(hal_start(control, &ctx));
    hal_sw_plant_run(sc.n_ticks());
    hal_sw_plant_detach();
    r.log = std::move(ctx.log);
    return r;
}

mcsim::Scenario experiment()
{
    return mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper000_experiment.toml");
}

// The experiment with a 20 ms burst of sensor noise (sigma noise_A) at kInject.
constexpr double kBurst_s = 0.02;
mcsim::Scenario experiment_with_burst(double noise_A)
{
    mcsim::Scenario sc = experiment();
    sc.faults.burst_t_s = kInject;
    sc.faults.burst_duration_s = kBurst_s;
    sc.faults.burst_noise_A = noise_A;
    return sc;
}

// Where the nominal experiment's rotor ends [rad]: a run that rides a fault
// through, or recovers from it, ends within 0.05 rad of it.
double nominal_end_theta_rad()
{
    static const double theta = run(experiment()).log.back().theta;
    return theta;
}

// What every fault run must show: the first fault's code and its detection
// within [kInject, kInject + within_s]; the drive in FAULT at the end when
// it must be (safe), no voltage step beyond the bounds, the currents within
// i_max at the end, finite estimates; and a snapshot whose newest record
// is the sample before the detection. Samples in [noisy_from_s, noisy_to_s]
// (a noise burst) are exempt from the voltage-step bounds: there the
// closed-loop law acts on the injected noise. inject_s: when the fault
// began (kInject unless it is there from the start).
void common_checks(const Result& r, drive_fault_t want, double within_s, bool safe_at_end, double noisy_from_s = 0.0,
                   double noisy_to_s = -1.0, double inject_s = kInject)
{
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
    ASSERT_TRUE(fr->frozen) << "no fault recorded";
    EXPECT_EQ(fr->fault, want) << drive_fault_name(fr->fault);
    const double t = r.t_first();
    EXPECT_GE(t, inject_s - 0.5 * r.ts);
    EXPECT_LE(t, inject_s + within_s + 0.5 * r.ts) << "detected " << (t - inject_s) * 1e3 << " ms after the injection";
    EXPECT_EQ(r.drive.sup.state == SUP_STATE_FAULT, safe_at_end);
    // voltage steps
    const double v_start_step = 3.01 * 3.0 * 1.01;  // R I_max of the rig, 1 % for the measured R
    double dv_prev = 0.0;
    for (std::size_t k = 1; k < r.log.size(); ++k) {
        const Period &a = r.log[k - 1], &b = r.log[k];
        const double dv = std::fmax(std::fabs(b.va - a.va), std::fabs(b.vb - a.vb));
        const double dv_before = dv_prev;
        dv_prev = dv;
        const bool to_safe = b.state == SUP_STATE_FAULT && a.state != SUP_STATE_FAULT;
        const bool in_safe = b.state == SUP_STATE_FAULT && a.state == SUP_STATE_FAULT;
        if (to_safe || in_safe) {
            EXPECT_EQ(b.va, 0.0);
            EXPECT_EQ(b.vb, 0.0);
            continue;
        }
        if (b.t >= noisy_from_s && b.t <= noisy_to_s) {
            continue;
        }
        if (a.state != b.state && (a.state == SUP_STATE_CLOSED_LOOP || b.state == SUP_STATE_CLOSED_LOOP)) {
            EXPECT_LE(dv - dv_before, kSwitchStepMax_V) << "switch " << a.state << " -> " << b.state << " at t = " << b.t;
        }
        EXPECT_LE(dv, v_start_step) << "at t = " << b.t;
    }
    // the end: currents within the limit, estimates finite
    const Period& e = r.log.back();
    EXPECT_LE(std::hypot(e.ia, e.ib), r.sc.i_max_A);
    EXPECT_TRUE(std::isfinite(mcsim::to_double(r.drive.est.pos.theta_est_rad)));
    EXPECT_TRUE(std::isfinite(mcsim::to_double(r.drive.est.mech.omega_est_rad_s)));
    // snapshot: full, newest = the sample before the detection (or the
    // detecting one when the fault came from the command's checks)
    ASSERT_EQ(flight_recorder_count(fr), FLIGHT_RECORDER_DEPTH);
    const flight_record_t* newest = flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH - 1);
    ASSERT_NE(newest, nullptr);
    EXPECT_GE(newest->tick + 1, fr->fault_tick);
    EXPECT_LE(newest->tick, fr->fault_tick);
    const flight_record_t* oldest = flight_recorder_get(fr, 0);
    EXPECT_EQ(newest->tick - oldest->tick, FLIGHT_RECORDER_DEPTH - 1);
    EXPECT_EQ(flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH), nullptr);
}

}  // namespace

// A current sample that freezes: bit-identical while the voltage moves by
// 2 V, for 5 ms (FAULT_STUCK_S): SENSOR_STUCK, safe state. The snapshot's
// last 40 records show phase a frozen.
TEST(Faults, StuckSampleIn5ms)
{
    mcsim::Scenario sc = experiment();
    sc.faults.stuck_t_s = kInject;
    sc.faults.stuck_phase = 0;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_SENSOR_STUCK, 5.1e-3, true);
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
    const flight_record_t* last = flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH - 1);
    for (unsigned k = FLIGHT_RECORDER_DEPTH - 40; k < FLIGHT_RECORDER_DEPTH; ++k) {
        EXPECT_EQ(mcsim::to_double(flight_recorder_get(fr, k)->i_A[0]), mcsim::to_double(last->i_A[0])) << k;
    }
}

// A NaN sample (float build; fixed point has no NaN, the backend gives 0):
// NON_FINITE on that very sample.
TEST(Faults, NonFiniteSampleAtOnce)
{
    if (MC_FIXED) GTEST_SKIP() << "no NaN in fixed point";
    mcsim::Scenario sc = experiment();
    sc.faults.nan_t_s = kInject;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_NON_FINITE, 0.0, true);
}

// Overruns flagged by the backend: the third within the leak window trips
// (FAULT_OVERRUN_LIMIT / FAULT_OVERRUN_WEIGHT), two samples after the first.
TEST(Faults, OverrunsOnTheThird)
{
    mcsim::Scenario sc = experiment();
    sc.faults.overrun_t_s = kInject;
    sc.faults.overrun_count = 5;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_OVERRUN, 2.0 * sc.ts_s, true);
}

// A locked rotor at speed: the back-EMF collapses (loss of synchronism
// within 10 ms); with the re-lock reaction configured, the re-locks fail
// (at most relock_max) and the drive goes to the safe state; with the
// default (safe at once) it stops at the first detection.
TEST(Faults, LockedRotor)
{
    mcsim::Scenario sc = experiment();
    sc.faults.locked_rotor_t_s = kInject;
    const Result safe = run(sc);
    common_checks(safe, DRIVE_FAULT_LOSS_OF_SYNC, 10e-3, true);
    EXPECT_EQ(safe.drive.relocks, 0);
    EXPECT_EQ(paper000_drive_flight_recorder(&safe.drive)->events, 1u);
    const Result r = run(sc, FAULT_REACT_RELOCK);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 10e-3, true);
    // it tried to re-lock (bounded), and the loss stood
    EXPECT_GE(r.drive.relocks, 1);
    EXPECT_LE(r.drive.relocks, r.drive.cfg.prot.relock_max);
}

// An open winding: no current in it, the observer's error grows: loss of
// synchronism within 40 ms (measured: 20 ms float, 32 ms fixed; the error
// must first exceed 0.5 A for 5 ms, which depends on where the winding's
// current was in its cycle), then the safe state.
TEST(Faults, OpenPhase)
{
    mcsim::Scenario sc = experiment();
    sc.faults.open_phase_t_s = kInject;
    sc.faults.open_phase = 0;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 40e-3, true);
}

// A 0.3 A offset on phase a (10 % of I_max) appearing in closed loop: the
// estimate drifts off; detected within 0.2 s, the safe state.
TEST(Faults, SensorOffset)
{
    mcsim::Scenario sc = experiment();
    sc.faults.offset_t_s = kInject;
    sc.faults.offset_A[0] = 0.3;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 0.2, true);
}

// A load beyond the motor's torque (1.2 N m > K I_max = 0.81 N m) for
// 0.1 s: the rotor is thrown back, detected within 30 ms (measured: 18 ms
// float, 25 ms fixed), the re-locks
// cannot catch a reference that has moved on: the safe state.
TEST(Faults, LoadBeyondTheMotorsTorque)
{
    mcsim::Scenario sc = experiment();
    sc.load = {{kInject, 1.2, 0.0}, {kInject + 0.1, 0.0, 0.0}};
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 30e-3, true);
}

// An ADC whose full scale (4 A) is below the trip (4.5 A) and a 3 A offset
// on phase a (a sensor gone to its supply): the samples sit at the rail:
// SENSOR_RAIL after 2 samples there (FAULT_RAIL_TICKS), before the
// observer's error (5 ms) calls it a loss of synchronism.
TEST(Faults, SampleAtTheRail)
{
    mcsim::Scenario sc = experiment();
    sc.sensor.adc_full_scale_A = 4.0;
    sc.faults.offset_t_s = kInject;
    sc.faults.offset_A[0] = 3.0;
    const Result r = run(sc);
    // the first sample at the rail comes when i_a + 3 A reaches 4 A: within
    // half an electrical period (7 ms at 9 rad/s) of the injection
    common_checks(r, DRIVE_FAULT_SENSOR_RAIL, 10e-3, true);
}

// A supply sag to 8 V for 0.3 s is ridden through (no fault, the move
// finishes within the experiment's threshold); to 1 V it is not: the rotor
// falls behind, and at the latest when the reference slows to omega_lim
// (1.68 s) the drive finds the estimate off the reference and goes to the
// safe state instead of handing a lost rotor to the open loop.
TEST(Faults, SupplySag)
{
    mcsim::Scenario sc = experiment();
    sc.faults.sag_t_s = kInject;
    sc.faults.sag_duration_s = 0.3;
    sc.faults.sag_v_max_V = 8.0;
    Result r = run(sc);
    EXPECT_FALSE(paper000_drive_flight_recorder(&r.drive)->frozen);
    EXPECT_NE(r.drive.sup.state, SUP_STATE_FAULT);
    sc.faults.sag_v_max_V = 1.0;
    r = run(sc);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 0.3, true);
}

// Cleared only by command: after a fault the drive stays in FAULT at 0 V
// whatever comes in; paper000_drive_clear_fault() starts it again from the
// alignment with no fault and an empty recorder.
TEST(Faults, ClearedOnlyByCommand)
{
    mcsim::Scenario sc = experiment();
    sc.faults.stuck_t_s = kInject;
    sc.faults.stuck_phase = 1;
    Result r = run(sc);
    ASSERT_EQ(r.drive.sup.state, SUP_STATE_FAULT);
    hal_sample_t in{};
    in.n_phases = 2;
    hal_command_t out{};
    for (int k = 0; k < 100; ++k) {
        EXPECT_FALSE(paper000_drive_step(&r.drive, &in, &out));
        EXPECT_EQ(mcsim::to_double(out.v_V[0]), 0.0);
    }
    EXPECT_EQ(r.drive.sup.fault, DRIVE_FAULT_SENSOR_STUCK);
    ASSERT_TRUE(paper000_drive_clear_fault(&r.drive));
    EXPECT_EQ(r.drive.sup.state, SUP_STATE_ALIGN);
    EXPECT_EQ(r.drive.sup.fault, DRIVE_FAULT_NONE);
    EXPECT_FALSE(paper000_drive_flight_recorder(&r.drive)->frozen);
    EXPECT_TRUE(paper000_drive_step(&r.drive, &in, &out));
}

// A burst of sensor noise, 20 ms at 1.5 s (injection's own random stream;
// docs/faults.md, "What recovers"). 0.8 A (sigma) is ridden through: no
// fault event, and the move ends where the nominal run's does (1.0 A too in
// float; in fixed point it is a loss of synchronism at 15 ms). 1.2 A makes
// the current observer's error persist: loss of synchronism within 11 ms
// (measured 10.8 ms), the safe state by default. Within the burst the
// closed-loop law's output moves by up to 17 V a sample (its current loop
// acts on 1.2 A of noise), so the voltage-step bound is checked outside it.
TEST(Faults, NoiseBurst)
{
    const Result ridden = run(experiment_with_burst(0.8));
    EXPECT_EQ(paper000_drive_flight_recorder(&ridden.drive)->events, 0u);
    EXPECT_NEAR(ridden.log.back().theta, nominal_end_theta_rad(), 0.05);
    const Result lost = run(experiment_with_burst(1.2));
    common_checks(lost, DRIVE_FAULT_LOSS_OF_SYNC, 11e-3, true, kInject, kInject + kBurst_s);
}

// The re-lock after a noise burst ([protection] loss_of_sync = "relock"):
// the 1.2 A burst of the test above, detected as a loss of synchronism, the
// drive falls back to the open loop, closes again and finishes the move
// within 0.05 rad of the nominal run's end, no fault standing. Its noisy
// samples reach 5.2 A while the current stays at 2 A, so this needs the
// over-current trip on two consecutive samples ([limits] i_trip_samples =
// 2): with the instantaneous trip the re-lock ends in an over-current
// fault. Measured on this one case (seed 1, at 1.5 s); the re-lock does not
// recover every burst (docs/faults.md).
TEST(Faults, NoiseBurstReLocked)
{
    mcsim::Scenario sc = experiment_with_burst(1.2);
    sc.los_relock = 1;
    sc.i_trip_samples = 2;
    // the scenario keys reach the design
    {
        paper000_drive_t d;
        mcsim::design_and_init_drive(sc, &d);
        EXPECT_EQ(d.cfg.prot.reaction[DRIVE_FAULT_LOSS_OF_SYNC], static_cast<std::uint8_t>(FAULT_REACT_RELOCK));
        EXPECT_EQ(d.cfg.faults.i_trip_samples, 2);
    }
    const Result r = run(sc, FAULT_REACT_RELOCK);
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
    EXPECT_GE(r.drive.relocks, 1);
    EXPECT_NE(r.drive.sup.state, SUP_STATE_FAULT) << drive_fault_name(r.drive.sup.fault);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_LOSS_OF_SYNC);  // recorded, not standing
    EXPECT_NEAR(r.log.back().theta, nominal_end_theta_rad(), 0.05);
    for (const Period& p : r.log) {
        ASSERT_LE(std::hypot(p.ia, p.ib), r.sc.i_max_A * 1.01) << "at t = " << p.t;
    }
    sc.i_trip_samples = 1;
    const Result tripped = run(sc, FAULT_REACT_RELOCK);
    EXPECT_EQ(tripped.drive.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(tripped.drive.sup.fault, DRIVE_FAULT_OVERCURRENT);
}

// The same burst with the load-angle law ([design] control_law =
// "load_angle", control/load_angle.h) and the trip on three consecutive
// samples: detected as a loss of synchronism, the drive holds the rotor on
// its spring while the loop is open, closes again and finishes the move
// within 0.05 rad of the nominal run's end. The voltage-step bounds, the
// snapshot and the current within i_max at the end as for every fault.
// During the burst the law's current loop answers the noise (the law
// runs at 0.97 i_max, its PI turns 1.2 A of noise into up to 27 V): the
// current stays below the trip, i_trip_A (3.8 A measured), and within 1 %
// of i_max from 5 ms after the burst (3.11 A at 0.3 ms after it, back
// within 1 % by 2.5 ms).
TEST(Faults, NoiseBurstReLockedLoadAngle)
{
    mcsim::Scenario sc = experiment_with_burst(1.2);
    sc.los_relock = 1;
    sc.i_trip_samples = 3;
    sc.control_law = 1;
    {
        paper000_drive_t d;
        mcsim::design_and_init_drive(sc, &d);
        EXPECT_EQ(d.cfg.law, P000_LAW_LOAD_ANGLE);
    }
    const Result r = run(sc, FAULT_REACT_RELOCK);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 11e-3, false, kInject, kInject + kBurst_s);
    EXPECT_GE(r.drive.relocks, 1);
    EXPECT_NEAR(r.log.back().theta, nominal_end_theta_rad(), 0.05);
    for (const Period& p : r.log) {
        ASSERT_LT(std::hypot(p.ia, p.ib), r.sc.i_trip_A) << "at t = " << p.t;
        if (p.t < kInject || p.t > kInject + kBurst_s + 5e-3) {
            ASSERT_LE(std::hypot(p.ia, p.ib), r.sc.i_max_A * 1.01) << "at t = " << p.t;
        }
    }
}

// A gain error on phase a's current sensor from 1.5 s (closed loop at
// 8 rad/s on the way to 18 rad): 0.9 is ridden through (the move ends where
// the nominal run's does). 0.8 is tolerated while the loop stays closed,
// but when it closes again on the way back (2.32 s, 0.82 s after the
// injection) the distorted currents turn the estimated speed within 5 ms:
// a loss of synchronism (measured 7 ms after the closing in float), the
// safe state.
TEST(Faults, SensorGain)
{
    mcsim::Scenario sc = experiment();
    sc.faults.gain_t_s = kInject;
    sc.faults.gain[0] = 0.9;
    const Result ridden = run(sc);
    EXPECT_EQ(paper000_drive_flight_recorder(&ridden.drive)->events, 0u);
    EXPECT_NEAR(ridden.log.back().theta, nominal_end_theta_rad(), 0.05);
    sc.faults.gain[0] = 0.8;
    const Result r = run(sc);
    common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 0.83, true);
}

// A drive designed for the wrong motor ([drive_model]): R +-50 %, L +-45 %,
// J x0.5 and x2 are ridden through, and K -30 % too (the closed-loop K
// identification corrects it); K +30 % and K x0.5 are lost after the loop
// closes and detected as a loss of synchronism within 0.3 s of the first
// closed-loop sample (measured 0.09-0.22 s in float, up to 0.25 s in fixed
// point), the safe state.
TEST(Faults, ParameterMismatch)
{
    struct Case {
        double mcsim::MotorParams::*field;
        double value;
        bool ridden;
    };
    const Case cases[] = {{&mcsim::MotorParams::R_ohm, 4.5, true},       {&mcsim::MotorParams::R_ohm, 2.0, true},
                          {&mcsim::MotorParams::L_H, 0.006, true},       {&mcsim::MotorParams::L_H, 0.013, true},
                          {&mcsim::MotorParams::J_kgm2, 6.4e-4, true},   {&mcsim::MotorParams::J_kgm2, 1.6e-4, true},
                          {&mcsim::MotorParams::K_Nm_per_A, 0.19, true}, {&mcsim::MotorParams::K_Nm_per_A, 0.35, false},
                          {&mcsim::MotorParams::K_Nm_per_A, 0.135, false}};
    for (const Case& c : cases) {
        mcsim::Scenario sc = experiment();
        sc.drive_model.*(c.field) = c.value;
        const Result r = run(sc);
        SCOPED_TRACE("drive model value " + std::to_string(c.value));
        if (c.ridden) {
            EXPECT_EQ(paper000_drive_flight_recorder(&r.drive)->events, 0u);
            EXPECT_NEAR(r.log.back().theta, nominal_end_theta_rad(), 0.05);
            continue;
        }
        double t_closed = -1.0;
        for (const Period& p : r.log) {
            if (p.state == SUP_STATE_CLOSED_LOOP) {
                t_closed = p.t;
                break;
            }
        }
        ASSERT_GE(t_closed, 0.0) << "the loop never closed";
        common_checks(r, DRIVE_FAULT_LOSS_OF_SYNC, 0.3, true, 0.0, -1.0, t_closed);
    }
}

// The nominal experiment, seeds 1-5, and the ideal scenario: no fault event
// at all (no false alarm of any criterion).
TEST(Faults, NoFalseAlarmOnTheNominalRuns)
{
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        mcsim::Scenario sc = experiment();
        sc.seed = seed;
        const Result r = run(sc);
        EXPECT_EQ(paper000_drive_flight_recorder(&r.drive)->events, 0u) << "seed " << seed << ": "
                                                               << drive_fault_name(paper000_drive_flight_recorder(&r.drive)->fault);
    }
    mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper000_ideal.toml");
    const Result r = run(sc);
    EXPECT_EQ(paper000_drive_flight_recorder(&r.drive)->events, 0u);
}

// ---- issue 26: over-current in the R/L measurement, spaced overruns, re-lock counts ----

// One sample of -4.6 A on phase b (beyond the 4.5 A trip) in the middle of
// the standstill R/L measurement that follows the alignment (state
// IDENTIFY, the plant's current about 2 A): OVERCURRENT on that very
// sample, detected at its tick, 0 V from it on (the common checks), the
// measurement never completed and the model's R kept; after the run the
// drive stays in FAULT at 0 V on ordinary samples until cleared.
TEST(Faults, OvercurrentSampleDuringTheRlMeasurement)
{
    mcsim::Scenario sc = experiment();
    sc.duration_s = 0.2;
    std::uint32_t at = 0;
    int state_before = -1;
    const Result r = run(sc, FAULT_REACT_SAFE, [&](const paper000_drive_t& d, hal_sample_t* s) {
        if (at == 0 && d.sup.state == SUP_STATE_IDENTIFY && d.rl_id.k == d.cfg.rl_id.window_ticks / 2) {
            at = d.tick;
            state_before = d.sup.state;
            s->i_A[1] = mc_from_double(-4.6);
        }
    });
    ASSERT_GT(at, 0u) << "the measurement never reached its middle";
    EXPECT_EQ(state_before, SUP_STATE_IDENTIFY);
    const double t_at = r.sc.t_start_s() + at * sc.ts_s;
    common_checks(r, DRIVE_FAULT_OVERCURRENT, 0.0, true, 0.0, -1.0, t_at);
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
    EXPECT_EQ(fr->fault_tick, at);
    EXPECT_EQ(fr->events, 1u);
    EXPECT_EQ(r.drive.sup.fault, DRIVE_FAULT_OVERCURRENT);
    EXPECT_EQ(r.drive.rl_id.state, RL_ID_RUNNING);
    EXPECT_EQ(r.drive.model.R_ohm, r.drive.cfg.model.R_ohm) << "a measured R replaced the model's";
    // the plant's current up to the glitch was the step's, well below the trip
    for (const Period& p : r.log) {
        if (p.t < t_at + 0.5 * sc.ts_s) {
            EXPECT_LT(std::hypot(p.ia, p.ib), 3.0) << "at t = " << p.t;
        }
    }
    paper000_drive_t d = r.drive;
    hal_sample_t in{};
    in.n_phases = 2;
    in.v_bus_V = mc_from_double(30.0);
    hal_command_t out{};
    for (int k = 0; k < 50; ++k) {
        in.i_A[0] = mc_from_double(0.01 * std::sin(0.3 * k));
        EXPECT_FALSE(paper000_drive_step(&d, &in, &out));
        EXPECT_EQ(mcsim::to_double(out.v_V[0]), 0.0);
        EXPECT_EQ(mcsim::to_double(out.v_V[1]), 0.0);
    }
    EXPECT_EQ(d.sup.fault, DRIVE_FAULT_OVERCURRENT);
}

// Overruns flagged apart from each other on the drive (a status bit the
// backend sets): one every 1001 samples from 1.5 s to the end is
// tolerated (the level, 1000 each, has leaked back to 0 before the next):
// no fault event, the move ends where the nominal run's does, every one
// counted. One every 501 samples trips on the 5th, on its very sample
// (1000 + 4 x 500 = 3000, the limit); one every 502 on the 6th.
TEST(Faults, SpacedOverrunsToleratedAndTheStatedCountTrips)
{
    auto spaced = [](std::uint32_t every, std::vector<std::uint32_t>* ticks) {
        return [every, ticks](const paper000_drive_t& d, hal_sample_t* s) {
            (void)d;
            if (s->tick >= ticks->front() && (s->tick - ticks->front()) % every == 0) {
                s->status |= HAL_STATUS_OVERRUN;
                if (s->tick != ticks->front()) ticks->push_back(s->tick);
            }
        };
    };
    mcsim::Scenario sc = experiment();
    {
        mcsim::Scenario probe = sc;
        paper000_drive_t d;
        mcsim::design_and_init_drive(probe, &d);
        sc.pre_ticks = probe.pre_ticks;
    }
    const std::uint32_t first = static_cast<std::uint32_t>(std::lround((kInject - sc.t_start_s()) / sc.ts_s));
    std::vector<std::uint32_t> ticks{first};
    const Result ok = run(sc, FAULT_REACT_SAFE, spaced(1001, &ticks));
    EXPECT_EQ(paper000_drive_flight_recorder(&ok.drive)->events, 0u) << drive_fault_name(paper000_drive_flight_recorder(&ok.drive)->fault);
    EXPECT_NE(ok.drive.sup.state, SUP_STATE_FAULT);
    EXPECT_EQ(ok.drive.mon.overruns, ticks.size());
    EXPECT_GT(ticks.size(), 25u);
    EXPECT_NEAR(ok.log.back().theta, nominal_end_theta_rad(), 0.05);
    for (const auto& [every, nth] : {std::pair<std::uint32_t, std::size_t>{501, 5}, {502, 6}}) {
        ticks.assign(1, first);
        sc.duration_s = kInject + 0.3;
        const Result r = run(sc, FAULT_REACT_SAFE, spaced(every, &ticks));
        SCOPED_TRACE("every " + std::to_string(every));
        ASSERT_EQ(ticks.size(), nth) << "the overruns went on after the trip, or it came early";
        const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
        ASSERT_TRUE(fr->frozen);
        EXPECT_EQ(fr->fault, DRIVE_FAULT_OVERRUN);
        EXPECT_EQ(fr->fault_tick, ticks.back());
        EXPECT_EQ(r.drive.mon.overruns, nth);
        common_checks(r, DRIVE_FAULT_OVERRUN, (nth - 1) * every * sc.ts_s, true);
    }
}

// The re-lock reaction after the 1.2 A noise burst with the instantaneous
// trip (see NoiseBurstReLocked): two re-locks, then an over-current trip
// on a noisy sample. Every re-lock is a fault event and so is the final
// trip: the recorder counts relocks + 1; its code and tick are the first
// loss of synchronism's (the sample on which the first re-lock started)
// while the supervisor's standing fault is the over-current, and its
// snapshot ends on the sample before the first loss, however many
// re-locks and samples followed.
TEST(Faults, ReLocksAreEachCountedAndTheFirstSnapshotKept)
{
    mcsim::Scenario sc = experiment_with_burst(1.2);
    sc.los_relock = 1;
    sc.duration_s = kInject + 0.2;
    const Result r = run(sc, FAULT_REACT_RELOCK);
    const flight_recorder_t* fr = paper000_drive_flight_recorder(&r.drive);
    ASSERT_EQ(r.drive.sup.state, SUP_STATE_FAULT);
    EXPECT_GE(r.drive.relocks, 2);
    EXPECT_LE(r.drive.relocks, r.drive.cfg.prot.relock_max);
    EXPECT_EQ(fr->events, static_cast<std::uint32_t>(r.drive.relocks) + 1u);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_LOSS_OF_SYNC);
    std::uint32_t first_relock = 0;
    int relocks_seen = 0;
    for (const Period& p : r.log) {
        if (p.relocks > relocks_seen) {
            EXPECT_EQ(p.relocks, relocks_seen + 1) << "two re-locks on one sample";
            if (relocks_seen == 0) first_relock = p.tick - 1;  // the sample that started it
            relocks_seen = p.relocks;
        }
    }
    EXPECT_EQ(relocks_seen, r.drive.relocks);
    EXPECT_EQ(fr->fault_tick, first_relock);
    ASSERT_EQ(flight_recorder_count(fr), FLIGHT_RECORDER_DEPTH);
    EXPECT_EQ(flight_recorder_get(fr, FLIGHT_RECORDER_DEPTH - 1)->tick + 1, first_relock);
    // the standing fault is the last one, the recorder names the first
    EXPECT_EQ(r.drive.sup.fault, DRIVE_FAULT_OVERCURRENT);
    paper000_telemetry_t tl;
    paper000_drive_get_telemetry(&r.drive, &tl);
    EXPECT_EQ(tl.fault_events, fr->events);
}

// ---- the paper-001 speed drive: the same fault set ----

namespace {

struct SpeedResult {
    paper001_drive_t drive;
    double t_first = -1.0;
    int last_state = 0;
    double i_end_A = 0.0;
};

void speed_control(void* p, const hal_sample_t* in, hal_command_t* out)
{
    if (!paper001_drive_step(static_cast<paper001_drive_t*>(p), in, out)) hal_safe_state();
}

SpeedResult run_speed(mcsim::Scenario sc)
{
    SpeedResult r;
    p001_design_report_t rep{};
    mcsim::design_and_init_speed_drive(sc, &r.drive, &rep);
    mcsim::Rig rig(sc);
    hal_sw_plant_attach(&rig.plant, &rig.sensor, rig.amp, sc.ts_s);
    mcsim::FaultInjector inj(sc.faults, sc.seed);
    hal_sw_plant_set_faults(&inj);
    EXPECT_TRUE(hal_start(speed_control, &r.drive));
    hal_sw_plant_run(sc.n_ticks());
    hal_sw_plant_detach();
    const flight_recorder_t* fr = paper001_flight_recorder(&r.drive);
    r.t_first = fr->frozen ? fr->fault_tick * sc.ts_s : -1.0;
    r.last_state = static_cast<int>(r.drive.sup.state);
    double i[3];
    rig.plant.phase_currents(i);
    r.i_end_A = std::fmax(std::fabs(i[0]), std::fmax(std::fabs(i[1]), std::fabs(i[2])));
    return r;
}

mcsim::Scenario benchmark()
{
    mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper001_benchmark.toml");
    sc.duration_s = 5.0;  // the faults are injected at 4 s, at 85 rpm on the ramp to 120
    return sc;
}

}  // namespace

// A locked rotor at 4 s: the IDA-PBC law drives the current up; the
// over-current trip ends it within 50 ms (measured 42 ms), the safe state,
// the phase currents decayed at the end.
TEST(FaultsSpeedDrive, LockedRotor)
{
    mcsim::Scenario sc = benchmark();
    sc.faults.locked_rotor_t_s = 4.0;
    const SpeedResult r = run_speed(sc);
    const flight_recorder_t* fr = paper001_flight_recorder(&r.drive);
    ASSERT_TRUE(fr->frozen);
    EXPECT_TRUE(fr->fault == DRIVE_FAULT_OVERCURRENT || fr->fault == DRIVE_FAULT_LOSS_OF_SYNC) << fr->fault;
    EXPECT_GE(r.t_first, 4.0);
    EXPECT_LE(r.t_first, 4.05);
    EXPECT_EQ(r.last_state, SUP_STATE_FAULT);
    EXPECT_LE(r.i_end_A, sc.i_max_A);
    EXPECT_EQ(flight_recorder_count(fr), FLIGHT_RECORDER_DEPTH);
}

// A frozen phase-b sample at 85 rpm: SENSOR_STUCK once its leg voltage has
// swung 2 V (a slow motor: within 0.1 s, measured 80 ms).
TEST(FaultsSpeedDrive, StuckSample)
{
    mcsim::Scenario sc = benchmark();
    sc.faults.stuck_t_s = 4.0;
    sc.faults.stuck_phase = 1;
    const SpeedResult r = run_speed(sc);
    const flight_recorder_t* fr = paper001_flight_recorder(&r.drive);
    ASSERT_TRUE(fr->frozen);
    EXPECT_EQ(fr->fault, DRIVE_FAULT_SENSOR_STUCK);
    EXPECT_LE(r.t_first, 4.1);
    EXPECT_EQ(r.last_state, SUP_STATE_FAULT);
    EXPECT_LE(r.i_end_A, sc.i_max_A);
    SpeedResult c = r;
    ASSERT_TRUE(paper001_drive_clear_fault(&c.drive));
    EXPECT_FALSE(paper001_flight_recorder(&c.drive)->frozen);
}

// No false alarm on the full benchmark (load steps, both estimators).
TEST(FaultsSpeedDrive, NoFalseAlarm)
{
    for (int est : {0, 1}) {
        mcsim::Scenario sc = mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper001_benchmark.toml");
        sc.speed_gains.estimator = est;
        const SpeedResult r = run_speed(sc);
        EXPECT_EQ(paper001_flight_recorder(&r.drive)->events, 0u) << "estimator " << est;
    }
}

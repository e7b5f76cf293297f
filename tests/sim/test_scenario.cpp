// Scenario files: the shipped ones parse to the paper's numbers and design a
// drive; overrides land in the right place; errors name the file and key.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "host_drives/paper000_host.h"
#include "scenario/scenario.h"

namespace {

namespace fs = std::filesystem;

const std::string kSrc = MC_SOURCE_DIR;

std::string scenario_path(const char* name) { return kSrc + "/sim/scenarios/" + name; }

// A scenario in a fresh temporary directory (never in the source tree).
class TempScenario {
public:
    explicit TempScenario(const std::string& text)
    {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = std::string(info->test_suite_name()) + "_" + info->name();
        for (char& ch : name) {
            ch = (ch == '/') ? '_' : ch;
        }
        dir_ = fs::temp_directory_path() / ("mcsim_test_" + std::to_string(::getpid()) + "_" + name);
        fs::create_directories(dir_);
        path_ = (dir_ / "scenario.toml").string();
        std::ofstream(path_) << text;
    }
    ~TempScenario() { fs::remove_all(dir_); }
    const std::string& path() const { return path_; }
    fs::path dir() const { return dir_; }

private:
    fs::path dir_;
    std::string path_;
};

const std::string kMotorLine = "file = \"" + kSrc + "/sim/motors/paper000_stepper.toml\"";

const std::string kBase = R"(
[run]
duration_s = 1.0
Ts_s = 1e-4
[motor]
)" + kMotorLine + R"(
[supply]
v_max_V = 30.0
[limits]
i_max_A = 3.0
omega_lim_rad_s = 3.0
[[trajectory.segments]]
t_start_s = 0.0
duration_s = 0.5
theta_to_rad = 2.0
)";

TEST(Scenario, PaperIdeal)
{
    const mcsim::Scenario sc = mcsim::load_scenario(scenario_path("paper000_ideal.toml"));
    EXPECT_EQ(sc.stem, "paper000_ideal");
    EXPECT_EQ(sc.motor.L_H, 9e-3);
    EXPECT_EQ(sc.motor.R_ohm, 3.01);
    EXPECT_EQ(sc.motor.K_Nm_per_A, 0.27);
    EXPECT_EQ(sc.motor.J_kgm2, 3.18e-4);
    EXPECT_EQ(sc.motor.fv_Nms_per_rad, 2.37e-3);
    EXPECT_EQ(sc.motor.coulomb_Nm, 0.0752);
    EXPECT_EQ(sc.motor.n_p, 50);
    EXPECT_EQ(sc.drive_model.L_H, sc.motor.L_H);
    EXPECT_EQ(sc.ts_s, 1e-4);
    EXPECT_EQ(sc.duration_s, 4.25);
    EXPECT_EQ(sc.n_ticks(), 42500u);
    EXPECT_EQ(sc.v_max_V, 30.0);
    EXPECT_EQ(sc.i_max_A, 3.0);
    EXPECT_EQ(sc.omega_lim_rad_s, 3.0);
    EXPECT_EQ(sc.sensor.noise, mcsim::NoiseKind::kNone);
    ASSERT_EQ(sc.segments.size(), 2u);
    EXPECT_EQ(sc.segments[0].t_start_s, 0.0);
    EXPECT_EQ(sc.segments[0].duration_s, 2.0);
    EXPECT_EQ(sc.segments[0].theta_to_rad, 18.0);
    EXPECT_EQ(sc.segments[1].t_start_s, 2.0);
    EXPECT_EQ(sc.segments[1].duration_s, 2.0);
    EXPECT_EQ(sc.segments[1].theta_to_rad, 0.0);
}

TEST(Scenario, PaperExperiment)
{
    const mcsim::Scenario sc = mcsim::load_scenario(scenario_path("paper000_experiment.toml"));
    EXPECT_EQ(sc.sensor.noise, mcsim::NoiseKind::kUniform);
    EXPECT_EQ(sc.sensor.noise_A, 0.03);
    EXPECT_EQ(sc.seed, 1u);
}

TEST(Scenario, ShippedScenariosDesignADrive)
{
    for (const char* name : {"paper000_ideal.toml", "paper000_experiment.toml"}) {
        mcsim::Scenario sc = mcsim::load_scenario(scenario_path(name));
        paper000_drive_t drive;
        EXPECT_NO_THROW(mcsim::design_and_init_drive(sc, &drive)) << name;
    }
}

TEST(Scenario, OverridesAndDesignMapping)
{
    const TempScenario t(kBase + R"(
[drive_model]
L_H = 10e-3
[load]
steps = [{t_s = 0.2, torque_Nm = 0.1}, {t_s = 0.5, torque_Nm = 0.0, ramp_s = 0.1}]
[gains]
k_surface_per_s = 80.0
[bounds]
bound_load_Nm = 0.2
)");
    // Plant override in [motor] as well.
    std::string text;
    {
        std::ifstream f(t.path());
        text.assign(std::istreambuf_iterator<char>(f), {});
    }
    const auto pos = text.find(kMotorLine);
    text.insert(text.find('\n', pos) + 1, "R_ohm = 3.5\n");
    std::ofstream(t.path()) << text;

    const mcsim::Scenario sc = mcsim::load_scenario(t.path());
    EXPECT_EQ(sc.motor.R_ohm, 3.5);
    EXPECT_EQ(sc.drive_model.R_ohm, 3.5);  // drive model defaults to the plant
    EXPECT_EQ(sc.motor.L_H, 9e-3);
    EXPECT_EQ(sc.drive_model.L_H, 10e-3);
    ASSERT_EQ(sc.load.size(), 2u);
    EXPECT_EQ(sc.load[1].ramp_s, 0.1);
    EXPECT_EQ(sc.i_trip_A, 4.5);  // default 1.5 i_max

    drive_design_input_t in;
    mcsim::make_design_input(sc, &in);
    EXPECT_EQ(in.motor.L_H, 10e-3);
    EXPECT_EQ(in.motor.R_ohm, 3.5);
    EXPECT_EQ(in.ts_s, 1e-4);
    EXPECT_EQ(in.n_segments, 1);
    EXPECT_EQ(in.segments[0].theta_to_rad, 2.0);
    EXPECT_EQ(in.override.k_surface_per_s, 80.0);
    EXPECT_EQ(in.bound_load_Nm, 0.2);
    EXPECT_EQ(in.i_trip_A, 4.5);
    EXPECT_EQ(in.control_law, P000_LAW_TWISTING);  // the paper's unless asked
}

// [inverter] pwm: absent or "averaged" the averaged legs, "switched" the
// legs at the carrier (20 kHz, two carrier periods per 100 us sample)
TEST(Scenario, InverterPwmModel)
{
    {
        const TempScenario t(kBase + "[inverter]\ndead_time_s = 500e-9\n");
        EXPECT_EQ(mcsim::load_scenario(t.path()).inverter.pwm, mcsim::PwmModel::kAveraged);
    }
    {
        const TempScenario t(kBase + "[inverter]\npwm = \"averaged\"\n");
        EXPECT_EQ(mcsim::load_scenario(t.path()).inverter.pwm, mcsim::PwmModel::kAveraged);
    }
    {
        const TempScenario t(kBase + "[inverter]\npwm = \"switched\"\n");
        const mcsim::Scenario sc = mcsim::load_scenario(t.path());
        EXPECT_EQ(sc.inverter.pwm, mcsim::PwmModel::kSwitched);
        EXPECT_EQ(sc.inverter.f_pwm_Hz, 20e3);
    }
}

TEST(Scenario, ControlLawMapsToTheDesign)
{
    const TempScenario t(kBase + "[design]\ncontrol_law = \"load_angle\"\n");
    const mcsim::Scenario sc = mcsim::load_scenario(t.path());
    drive_design_input_t in;
    mcsim::make_design_input(sc, &in);
    EXPECT_EQ(in.control_law, P000_LAW_LOAD_ANGLE);
}

struct BadCase {
    const char* name;
    const char* edit_from;  // replaced in kBase ("" = append edit_to; "MOTOR" = the motor line)
    const char* edit_to;
    const char* key;        // must appear in the message
};

class ScenarioErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(ScenarioErrors, OneLineNamingFileAndKey)
{
    const BadCase& c = GetParam();
    std::string text = kBase;
    const std::string from = (std::string(c.edit_from) == "MOTOR") ? kMotorLine : c.edit_from;
    std::string to = c.edit_to;
    if (to.rfind("MOTOR", 0) == 0) {
        to = kMotorLine + to.substr(5);
    }
    if (from.empty()) {
        text += to;
    } else {
        const auto p = text.find(from);
        ASSERT_NE(p, std::string::npos);
        text.replace(p, from.size(), to);
    }
    const TempScenario t(text);
    try {
        mcsim::load_scenario(t.path());
        FAIL() << "no error for " << c.name;
    } catch (const mcsim::ScenarioError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        EXPECT_EQ(msg.rfind(t.path() + ":", 0), 0u) << msg;
        EXPECT_NE(msg.find(c.key), std::string::npos) << msg;
    }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ScenarioErrors,
    ::testing::Values(BadCase{"unknown_key", "Ts_s = 1e-4", "Ts_s = 1e-4\nTs = 1", "run.Ts: unknown key"},
                      BadCase{"unknown_table", "", "[foo]\nx = 1\n", "foo: unknown key"},
                      BadCase{"wrong_type", "duration_s = 1.0", "duration_s = \"1\"", "run.duration_s: expected a number"},
                      BadCase{"subtable", "", "[motor.x]\n", "motor.x: unknown key"},
                      BadCase{"missing", "Ts_s = 1e-4", "", "run.Ts_s: missing"},
                      BadCase{"L", "MOTOR",
                              "MOTOR\nL_H = -1", "motor.L_H: must be > 0 (got -1)"},
                      BadCase{"R", "MOTOR",
                              "MOTOR\nR_ohm = -0.1", "motor.R_ohm: must be >= 0"},
                      BadCase{"J", "MOTOR",
                              "MOTOR\nJ_kgm2 = 0", "motor.J_kgm2: must be > 0"},
                      BadCase{"n_p", "MOTOR",
                              "MOTOR\nn_p = 0", "motor.n_p"},
                      BadCase{"n_p_float", "MOTOR",
                              "MOTOR\nn_p = 50.0", "motor.n_p: expected an integer"},
                      BadCase{"drive_model_L", "", "[drive_model]\nL_H = 0\n", "drive_model.L_H: must be > 0"},
                      BadCase{"Ts", "Ts_s = 1e-4", "Ts_s = 0", "run.Ts_s: must be > 0"},
                      BadCase{"duration", "duration_s = 1.0", "duration_s = -1.0", "run.duration_s: must be > 0"},
                      BadCase{"segment_duration", "duration_s = 0.5", "duration_s = -0.5",
                              "trajectory.segments[0].duration_s: must be > 0"},
                      BadCase{"segment_overlap", "", "[[trajectory.segments]]\nt_start_s = 0.2\nduration_s = 1\ntheta_to_rad = 0\n",
                              "trajectory.segments[1].t_start_s"},
                      BadCase{"noise", "", "[sensor]\nnoise = \"uniform\"\nnoise_A = -0.1\n", "sensor.noise_A: must be >= 0"},
                      BadCase{"noise_kind", "", "[sensor]\nnoise = \"pink\"\n", "sensor.noise"},
                      BadCase{"noise_missing_size", "", "[sensor]\nnoise = \"gaussian\"\n", "sensor.noise_A: missing"},
                      BadCase{"i_trip", "i_max_A = 3.0", "i_max_A = 3.0\ni_trip_A = 2.0", "limits.i_trip_A"},
                      BadCase{"i_trip_samples_0", "i_max_A = 3.0", "i_max_A = 3.0\ni_trip_samples = 0",
                              "limits.i_trip_samples: must be 1..8 (got 0)"},
                      BadCase{"i_trip_samples_9", "i_max_A = 3.0", "i_max_A = 3.0\ni_trip_samples = 9",
                              "limits.i_trip_samples: must be 1..8 (got 9)"},
                      BadCase{"i_trip_samples_float", "i_max_A = 3.0", "i_max_A = 3.0\ni_trip_samples = 2.0",
                              "limits.i_trip_samples: expected an integer"},
                      BadCase{"loss_of_sync", "", "[protection]\nloss_of_sync = \"retry\"\n",
                              "protection.loss_of_sync: must be \"safe\" or \"relock\" (got \"retry\")"},
                      BadCase{"control_law", "", "[design]\ncontrol_law = \"spring\"\n",
                              "design.control_law: must be \"twisting\" or \"load_angle\" (got \"spring\")"},
                      BadCase{"protection_key", "", "[protection]\nstall = \"safe\"\n", "protection.stall: unknown key"},
                      BadCase{"gain_name", "", "[gains]\nemf_alpha = 1.0\n", "gains.emf_alpha: unknown key"},
                      BadCase{"nan", "v_max_V = 30.0", "v_max_V = nan", "supply.v_max_V: must be finite"},
                      BadCase{"motor_file", "paper000_stepper.toml", "nope.toml", "motor.file: cannot open"},
                      BadCase{"syntax", "", "[run\n", ""},
                      // found by tests/fuzz: refused before toml++ 3.3.0 reaches undefined behaviour
                      BadCase{"non_ascii_key", "", "Φ_Wb = 0.01\n",
                              ":16:1: non-ASCII character (U+03A6) outside a string or a comment"},
                      BadCase{"non_ascii_after_value", "v_max_V = 30.0", "v_max_V = 30.0 Ω",
                              ":8:16: non-ASCII character (U+03A9) outside a string or a comment"},
                      BadCase{"non_ascii_after_quote_in_value", "v_max_V = 30.0", "v_max_V = -'3Ͽ",
                              ":8:14: non-ASCII character (U+03FF) outside a string or a comment"},
                      BadCase{"non_ascii_after_backslash", "", "description = \"\"\"a\\Ω\"\"\"\n",
                              ":16:20: non-ASCII character (U+03A9) right after a backslash in a multi-line string"},
                      // [inverter] pwm (issue 30): its two values, and the switched legs
                      // need a whole number of carrier periods per control period
                      BadCase{"inverter_pwm_kind", "", "[inverter]\npwm = \"carrier\"\n",
                              "inverter.pwm: must be \"averaged\" or \"switched\" (got \"carrier\")"},
                      BadCase{"inverter_pwm_ratio", "", "[inverter]\nf_pwm_Hz = 24000\npwm = \"switched\"\n",
                              "inverter.pwm: \"switched\" needs a whole number (1 to 128) of PWM periods per control "
                              "period: f_pwm_Hz = 24000 Hz is 2.4 times the control rate 1/run.Ts_s = 10000 Hz"},
                      // a control character in a key: the message stays one line
                      BadCase{"key_control_char", "v_max_V = 30.0", "v_max_V = 30.0\n\"v\\nV\" = 1",
                              "supply.v\\nV: unknown key"}),
    [](const ::testing::TestParamInfo<BadCase>& i) { return std::string(i.param.name); });

TEST(Scenario, MotorFileErrorsNameTheMotorFile)
{
    // Relative motor path: resolved against the scenario's directory.
    std::string text = kBase;
    text.replace(text.find(kMotorLine), kMotorLine.size(), "file = \"motors/bad_motor.toml\"");
    const TempScenario t(text);
    fs::create_directories(t.dir() / "motors");
    std::ofstream((t.dir() / "motors" / "bad_motor.toml").string())
        << "type = \"stepper2\"\nL_H = 9e-3\nR_ohm = -3\nK_Nm_per_A = 0.27\nJ_kgm2 = 3e-4\nfv_Nms_per_rad = 0\nn_p = 50\n";
    try {
        mcsim::load_scenario(t.path());
        FAIL();
    } catch (const mcsim::ScenarioError& e) {
        EXPECT_NE(std::string(e.what()).find("motors/bad_motor.toml: R_ohm: must be >= 0 (got -3)"), std::string::npos)
            << e.what();
    }
}

// Non-ASCII characters where TOML allows them: comments and every kind of
// string (the check that keeps toml++ 3.3.0 away from the others must not
// refuse these), after a UTF-8 byte order mark.
TEST(Scenario, NonAsciiInCommentsAndStringsIsRead)
{
    const TempScenario a("\xEF\xBB\xBF# Φ_Wb = 0.01, ω in rad/s\ndescription = \"θ ± 5 %, 'Ω' \\\"Φ\\\"\"  # Ω\n" + kBase);
    EXPECT_EQ(mcsim::load_scenario(a.path()).description, "θ ± 5 %, 'Ω' \"Φ\"");
    const TempScenario b("description = '''Φ ''Ω'' θ'''''\n" + kBase);
    EXPECT_EQ(mcsim::load_scenario(b.path()).description, "Φ ''Ω'' θ''");
    const TempScenario c("description = \"\"\"\nω \"\"Φ\"\" \\\n   x Ω\"\"\"\n" + kBase);
    EXPECT_EQ(mcsim::load_scenario(c.path()).description, "ω \"\"Φ\"\" x Ω");
    const TempScenario d("description = 'Ω'\n" + kBase + "[expect.\"θ\"]\nmax = 1.0\n");
    EXPECT_EQ(mcsim::load_scenario(d.path()).expect.at(0).metric, "θ");
    // in arrays, inline tables and headers too: toml++ reads them (these
    // scenarios are then wrong for other reasons, named in the message)
    for (const char* extra : {"[sensor]\nnoise=[\"θ\",'Ω']\n",
                              "[sensor]\nnoise = { a = \"θ\", b = [\n  'Ω', # ω\n  \"\"\"Φ\"\"\" ] }\n",
                              "[\"θ\".x]\n", "[[trajectory.'Ω']]\n"}) {
        const TempScenario e(kBase + extra);
        try {
            mcsim::load_scenario(e.path());
            ADD_FAILURE() << "no error for " << extra;
        } catch (const mcsim::ScenarioError& err) {
            EXPECT_EQ(std::string(err.what()).find("non-ASCII"), std::string::npos) << err.what();
        }
    }
}

TEST(Scenario, MissingScenarioFile)
{
    EXPECT_THROW(mcsim::load_scenario(kSrc + "/sim/scenarios/does_not_exist.toml"), mcsim::ScenarioError);
}

}  // namespace

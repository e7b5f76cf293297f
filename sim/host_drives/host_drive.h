// host_drive.h - a drive's host part: what motorsim needs to run a drive
// of the firmware registry (firmware/drives/registry.h) from a scenario.
// Each drive that is chosen by [drive] kind = "<name>" brings one: the
// keys of its own scenario table (parsed and validated with the scenario's
// toml_view.h, errors naming file and key), the design of its
// configuration from the scenario, and its answers to the programs'
// per-drive questions (its estimators and which one a configuration runs,
// its reference's peak demand, how a replay tells it the applied voltage,
// how motorsim scores its runs, its commissioning). The programs look drives up here
// and never name one; a drive is added with its file in sim/host_drives/ and
// one line in host_registry.cpp.
#ifndef MCSIM_DRIVES_HOST_DRIVE_H
#define MCSIM_DRIVES_HOST_DRIVE_H

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "scenario/scenario.h"

extern "C" {
#include "drives/registry.h"
#include "config/params.h"
#include "startup/pmsm_identification.h"
}

namespace mcsim {

// One TOML table with its file and key prefix (scenario/toml_view.h, which a
// host part's parser includes; the programs that only run drives do not
// compile toml++).
class View;

// HostDrive.params of a drive: its generated table where this build has
// the parameters (float: firmware/CMakeLists.txt's mc_params), else none.
#if MC_HAS_PARAMS
#define MC_HOST_PARAMS(table) (&(table))
#else
#define MC_HOST_PARAMS(table) nullptr
#endif

struct HostDrive {
    const char* name;   // the firmware registry's name, and [drive] kind's
    // Its scenario table, [<table>]: the drive's name for a drive added
    // with [drive] kind; for the papers' drives the table that chose them
    // before [drive] kind existed ([trajectory], [speed], [paper002]),
    // which still does (without [drive], the drive whose table is there).
    const char* table;
    // Its table needs [drive] kind (a drive added since [drive] kind
    // exists); false: the table alone chooses the drive (the papers').
    bool needs_kind;
    // Parses [<table>] (absent: t is nullptr) when this is the scenario's
    // drive: each key validated into sc (sc->speed_points,
    // sc->drive_params, the drive's fields of Scenario), after every shared
    // table and every part's parse_extra. Throws ScenarioError.
    void (*parse)(const View* t, Scenario* sc);
    // The configuration from the scenario (motor, limits, Ts, delay, the
    // table's keys), tried on the drive once so that a refusal names the
    // scenario's field (throws ScenarioError "FILE: design: ..."). May set
    // what the run takes from the design: sc->pre_ticks, the samples the
    // drive runs before t = 0 (paper 000's rotor alignment).
    void (*design)(Scenario& sc, drive_config_storage_t* cfg);
    // The keys of [<table>], for sim/scenarios/README.md and the checks.
    std::vector<std::string> (*keys)();
    // The keys of the further tables the part reads (nullptr: none), as
    // (table, keys): sub-tables of [<table>] ("trajectory.segments") and
    // top-level tables of its own (paper 000's [design], [protection],
    // [gains], [bounds]); the top-level ones are keys of a scenario.
    std::vector<std::pair<std::string, std::vector<std::string>>> (*extra_keys)();
    // Reads the part's own top-level tables other than [<table>] from the
    // scenario's root (nullptr: it has none), after every shared table and
    // before the scenario's drive's parse, in every scenario whichever
    // drive it runs (sc->drive_kind): the papers' drives shared these
    // tables before a scenario named its drive, and a scenario of another
    // drive may still carry them; the part refuses there only what its
    // drive alone can do (paper 000's load-angle law, its re-lock).
    void (*parse_extra)(const View& root, Scenario* sc);
    // --estimator NAME (nullptr: the drive has one estimator): sets it in
    // *sc, or throws std::invalid_argument naming the choices.
    void (*select_estimator)(Scenario* sc, const std::string& name);
    // The reference's peak speed [rad/s] and acceleration [rad/s^2], for
    // motorsim's feasibility warning (nullptr: from sc.speed_points).
    void (*peak_demand)(const Scenario& sc, double* w_pk_rad_s, double* a_pk_rad_s2);
    // Open-loop replay of a recorded run (sim/replay/drive_replay.cpp;
    // nullptr: the drive cannot be replayed): tells the drive d, for its
    // next step only, the phase voltages v_V[0..n_phases) [V] really
    // applied over the coming sample, so that its estimator sees the
    // voltage that made the recorded currents rather than its own command.
    void (*set_applied_voltage)(drive_t* d, const double* v_V, int n_phases);
    // The estimator the configuration *cfg runs, named as --estimator and
    // the table's estimator key name it (nullptr: the drive has one
    // estimator), for the tools' records (mc_pil_gen's source line of its
    // vectors and of a board's configuration).
    const char* (*estimator_name)(const drive_config_storage_t* cfg);
    // How motorsim scores its runs (motorsim/run_recorder.h: "position",
    // "speed", "ekf_speed"; nullptr: by the drive's kind, "position" or
    // "speed").
    const char* scoring;
    // The commissioning run before the design (nullptr: the drive has
    // none): false when the scenario asks for none; else the PMSM
    // identification's configuration (firmware/startup/pmsm_identification.h)
    // in *cfg and its nominal length in *duration_s, which motorsim runs on
    // the scenario's plant and whose R, L and Phi replace sc.drive_model's
    // (motorsim/commission.h). Throws ScenarioError when it cannot be
    // designed.
    bool (*pmsm_identification)(const Scenario& sc, pmsm_id_config_t* cfg, double* duration_s);
    // Its user parameters, served over CAN and kept in motorsim's
    // --flash-image (the table generated from firmware/drives/<name>/
    // params.toml over its design input; nullptr: none, or a build without
    // them, the fixed-point one). With them: the design input they set,
    // from the scenario (input_bytes long), and the configuration from
    // such an input as design makes it from the scenario (the scenario's
    // board adds its dead-time compensation), tried on the drive; throws
    // ScenarioError "FILE: design: ...". design is these two in turn.
    const param_table_t* params;
    std::size_t input_bytes;
    void (*design_input)(const Scenario& sc, void* input);
    void (*design_from_input)(Scenario& sc, const void* input, drive_config_storage_t* cfg);
};

// The drive of that name, or nullptr.
const HostDrive* host_drive_find(const std::string& name);
// The drive whose table is [table], or nullptr.
const HostDrive* host_drive_of_table(const std::string& table);

// The scenario's drive (sc.drive_kind), designed by its host part into
// *cfg and initialised through the drive interface in *storage: its
// handle. Throws ScenarioError naming the file ("FILE: drive.kind: ..."
// when this build lacks the drive, "FILE: design: ..." when the design or
// the drive refuses). The design may set sc.pre_ticks.
drive_t design_scenario_drive(Scenario& sc, drive_storage_t* storage, drive_config_storage_t* cfg);
// Every registered host part.
const std::vector<const HostDrive*>& host_drives();

}  // namespace mcsim

#endif  // MCSIM_DRIVES_HOST_DRIVE_H

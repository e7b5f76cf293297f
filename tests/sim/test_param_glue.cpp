// sim.ParamGlue.*: motorsim's drive with its user parameters
// (sim/motorsim/param_glue.h over firmware/config/param_service.h and the
// file-backed flash, sim/motorsim/flash_file.h): a parameter written while
// disabled designs the drive again; saved, it is read back by a second
// motorsim on the same --flash-image and the drive is designed from it, as
// the host designs that input; a write refused while enabled, an image of
// the wrong size refused naming the file, the store's record surviving a
// reopen as a file.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

#include "host_drives/host_drive.h"
#include "motorsim/flash_file.h"
#include "motorsim/param_glue.h"

extern "C" {
#include "design/paper001_design.h"
#include "drives/paper001/generated/paper001_params.h"
}

namespace {

namespace fs = std::filesystem;

struct SimRun {
    mcsim::Scenario sc;
    const mcsim::HostDrive* host;
    std::unique_ptr<mcsim::ParamGlue> glue;
    std::unique_ptr<drive_storage_t> storage = std::make_unique<drive_storage_t>();
    std::unique_ptr<drive_config_storage_t> cfg = std::make_unique<drive_config_storage_t>();
    drive_t drive{};

    explicit SimRun(const std::string& image)
        : sc(mcsim::load_scenario(std::string(MC_SOURCE_DIR) + "/sim/scenarios/paper001_benchmark.toml")),
          host(mcsim::host_drive_find("paper001"))
    {
        glue = std::make_unique<mcsim::ParamGlue>(sc, *host, image);
        drive = glue->start(storage.get(), cfg.get());
    }
    can_param_answer_t ask(uint8_t op, uint16_t id = 0, uint32_t bits = 0)
    {
        can_cmd_t c{};
        c.kind = CAN_CMD_PARAM;
        c.param_op = op;
        c.param_seq = 1;
        c.param_id = id;
        c.param_value = bits;
        can_param_answer_t a{};
        mcsim::ParamGlue::answer(glue.get(), &c, &a);
        return a;
    }
    void enable(bool on)
    {
        drive_cmd_t c{};
        c.kind = DRIVE_CMD_ENABLE;
        c.enable = on;
        ASSERT_EQ(drive_command(&drive, &c), DRIVE_REFUSE_NONE);
    }
    bool enabled() const
    {
        drive_status_t s{};
        drive_status(&drive, &s);
        return s.enabled;
    }
};

uint32_t bits(float x)
{
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

std::string temp_image(const char* name)
{
    const fs::path p =
        fs::temp_directory_path() / (std::string("motorsim_") + name + "_" + std::to_string(::getpid()) + ".img");
    fs::remove(p);
    return p.string();
}

TEST(ParamGlue, ASavedParameterDesignsTheDriveOfTheNextRun)
{
    const std::string img = temp_image("saved");
    double R_scenario = 0.0;
    paper001_config_t designed{};
    {
        SimRun a(img);
        R_scenario = a.sc.drive_model.R_ohm;
        EXPECT_FALSE(fs::exists(img));  // nothing written until a save
        EXPECT_TRUE(a.enabled());
        const float R_new = static_cast<float>(R_scenario * 1.2);
        EXPECT_EQ(a.ask(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(R_new)).status, PARAM_ERR_NOT_WHILE_ENABLED);
        a.enable(false);
        const paper001_config_t before = a.cfg->paper001;
        const can_param_answer_t w = a.ask(PARAM_OP_WRITE, PAPER001_PARAMS_R_OHM, bits(R_new));
        ASSERT_EQ(w.status, PARAM_OK);
        EXPECT_EQ(w.value, bits(R_new));
        EXPECT_NE(std::memcmp(&before, &a.cfg->paper001, sizeof(before)), 0);  // designed again
        EXPECT_FALSE(a.enabled());                                             // and left disabled
        ASSERT_EQ(a.ask(PARAM_OP_SAVE).status, PARAM_OK);
        designed = a.cfg->paper001;
        EXPECT_EQ(fs::file_size(img), 2u * mcsim::FlashFile::kSectorWords * 4u);
    }
    SimRun b(img);
    EXPECT_EQ(b.ask(PARAM_OP_READ, PAPER001_PARAMS_R_OHM).value, bits(static_cast<float>(R_scenario * 1.2)));
    EXPECT_EQ(std::memcmp(&designed, &b.cfg->paper001, sizeof(designed)), 0);
    EXPECT_NE(b.glue->summary().find("record 1"), std::string::npos) << b.glue->summary();
    // the same as the host designs the scenario with that resistance
    mcsim::Scenario sc = b.sc;
    p001_design_input_t in{};
    b.host->design_input(sc, &in);
    in.motor.R_ohm = static_cast<double>(static_cast<float>(R_scenario * 1.2));
    drive_config_storage_t ref{};
    b.host->design_from_input(sc, &in, &ref);
    EXPECT_EQ(std::memcmp(&ref.paper001, &b.cfg->paper001, sizeof(ref.paper001)), 0);
    fs::remove(img);
}

TEST(ParamGlue, ARefusedDesignKeepsTheDriveFromBeingEnabledAndIsNotSaved)
{
    const std::string img = temp_image("refused");
    SimRun a(img);
    a.enable(false);
    // a trip current below the current limit: in range, refused by the design
    const float i_max = static_cast<float>(a.sc.i_max_A);
    const can_param_answer_t w = a.ask(PARAM_OP_WRITE, PAPER001_PARAMS_I_TRIP_A, bits(i_max * 0.5f));
    EXPECT_EQ(w.status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_FALSE(a.glue->ready());
    EXPECT_EQ(a.ask(PARAM_OP_SAVE).status, PARAM_ERR_DESIGN_REFUSED);
    EXPECT_FALSE(fs::exists(img));
    ASSERT_EQ(a.ask(PARAM_OP_DEFAULTS).status, PARAM_OK);  // the scenario's values design again
    EXPECT_TRUE(a.glue->ready());
}

TEST(ParamGlue, AnImageOfTheWrongSizeIsRefusedNamingIt)
{
    const std::string img = temp_image("bad");
    {
        std::ofstream f(img, std::ios::binary);
        f << "not a flash image";
    }
    try {
        SimRun a(img);
        FAIL() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(img), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("17 bytes"), std::string::npos) << e.what();
    }
    fs::remove(img);
    const std::string dir = fs::temp_directory_path().string();
    try {
        SimRun a(dir);
        FAIL() << "a directory accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
    }
}

}  // namespace

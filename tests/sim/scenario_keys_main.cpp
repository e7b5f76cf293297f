// scenario_keys - prints every scenario table's keys as the parser knows
// them (mcsim::scenario_keys(): its own tables, the top level, the motor
// file's, [gains], [bounds], each drive's table from its host part), one
// table per line: "TABLE KEY KEY ...". ctest docs.scenario_keys compares
// sim/scenarios/README.md with it (tests/sim/check_scenario_keys.py).
#include <cstdio>

#include "scenario/scenario.h"

int main()
{
    for (const auto& [table, keys] : mcsim::scenario_keys()) {
        std::printf("%s", table.c_str());
        for (const auto& k : keys) {
            std::printf(" %s", k.c_str());
        }
        std::printf("\n");
    }
    return 0;
}

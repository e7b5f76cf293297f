/*
 * board_chain.h - the signal chain of a DAC/ADC board between the drive
 * and a linear power stage (paper 000's dSpace DS1104 set-up: voltages out
 * on D/A channels through linear amplifiers to the windings, currents back
 * from Hall-effect sensors on A/D channels): the channel map, converter
 * codes to volts and back (bipolar +-range, offset binary codes 0..maxdata
 * as Comedi gives them), A/D volts to amperes through the sensor's gain and
 * its calibrated offset, phase volts to D/A volts through the amplifier's
 * gain, clamped at the converter and at the supply; and the start-up
 * calibration of the sensors' offsets with the outputs at zero, which
 * refuses to start when one is out of range. Used by the emulated board
 * (the simulator) and the Comedi driver alike. Pure functions of the
 * configuration; nothing allocates.
 */
#ifndef BOARD_CHAIN_H
#define BOARD_CHAIN_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define BOARD_MAX_PHASES 3
#define BOARD_MAX_CHANNELS 64

typedef struct {
    int n_phases;                      /* 2 or 3 */
    int ai_channels, ao_channels;      /* the card's channel counts */
    int current_ai[BOARD_MAX_PHASES];  /* A/D channel of each phase current */
    int vbus_ai;                       /* A/D channel of the bus voltage, -1: none (the supply's nominal) */
    int voltage_ao[BOARD_MAX_PHASES];  /* D/A channel of each phase voltage */
    int adc_bits, dac_bits;            /* 1..24 */
    double adc_range_V, dac_range_V;   /* bipolar: +-range */
    double sensor_V_per_A;             /* Hall sensor gain (nominal) */
    double amplifier_V_per_V;          /* phase volts per D/A volt */
    double vbus_V_per_V;               /* bus volts per A/D volt (divider) */
    double supply_V;                   /* the amplifiers' supply: the largest phase voltage */
    double offset_max_V;               /* the calibration's limit on a sensor offset */
} board_chain_config_t;

typedef struct {
    board_chain_config_t cfg;
    double offset_V[BOARD_MAX_PHASES]; /* measured sensor offsets (0 before the calibration) */
    bool calibrated;
} board_chain_t;

/* Checks cfg: channel counts and every channel within them, no channel
 * used twice (A/D or D/A), phase count, bits, ranges and gains > 0, the D/A
 * range times the amplifier's gain at least the supply (else the drive
 * could not use its supply), the bus divider able to hold the supply, the
 * calibration's limit inside the A/D range. Returns false with the offending key (the scenario's names, e.g.
 * "board.current_channels") and why in err. */
bool board_chain_check(const board_chain_config_t *cfg, char *err, int err_len);

void board_chain_init(board_chain_t *b, const board_chain_config_t *cfg);

/* Converter codes and volts: maxdata = 2^bits - 1, code 0 = -range,
 * maxdata = +range; to-code rounds and clamps. */
double board_code_to_volts(uint32_t code, int bits, double range_V);
uint32_t board_volts_to_code(double v, int bits, double range_V);

/* The same at the level of volts (a card whose driver converts codes to
 * volts with its own calibration, board_comedi.h): phase k's A/D volts to
 * amperes; the bus's A/D volts to volts; phase volts to D/A volts. */
double board_current_from_V(const board_chain_t *b, int k, double v_adc);
double board_vbus_from_V(const board_chain_t *b, double v_adc);
double board_dac_V(const board_chain_t *b, double v_phase_V, bool *clamped);

/* A/D codes of phase k's current to amperes: (volts - offset)/gain. */
double board_current_A(const board_chain_t *b, int k, uint32_t code);
/* A/D code of the bus voltage to volts (the supply if there is no channel). */
double board_vbus_V(const board_chain_t *b, uint32_t code);
/* Phase k's voltage to its D/A code: clamped at the supply, divided by the
 * amplifier's gain, clamped at the converter. *clamped tells if either. */
uint32_t board_voltage_code(const board_chain_t *b, double v_phase_V, bool *clamped);

/* The calibration: the mean A/D volts of each current channel over the
 * samples taken with the outputs at zero (sum_V[k] over n) become the
 * offsets. False, with the phase and the value in err, if one is beyond
 * offset_max_V: the board must not start. */
bool board_chain_calibrate(board_chain_t *b, const double *sum_V, int n, char *err, int err_len);

#ifdef __cplusplus
}
#endif

#endif /* BOARD_CHAIN_H */

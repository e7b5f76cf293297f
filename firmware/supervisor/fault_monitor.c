#include "supervisor/fault_monitor.h"

void fault_monitor_init(fault_monitor_t *m, const fault_monitor_config_t *cfg)
{
    m->cfg = *cfg;
    m->i2_sum_A2 = MC_ZERO;
    m->i2_n = 0;
    m->i2t_A2 = MC_ZERO;
    m->sat_run = 0;
    for (uint32_t k = 0; k < HAL_MAX_PHASES; ++k) {
        m->i_last_A[k] = MC_ZERO;
        m->same_run[k] = 0;
        m->v_lo_V[k] = MC_ZERO;
        m->v_hi_V[k] = MC_ZERO;
        m->v_last_V[k] = MC_ZERO;
    }
    m->oc_run = 0;
    m->rail_run = 0;
    m->rail_abs_A = mc_gt(cfg->i_rail_A, MC_ZERO) ? cfg->i_rail_A : MC_MAX;
    m->overrun_level = 0;
    m->overruns = 0;
}

drive_fault_t fault_monitor_sample(fault_monitor_t *m, const hal_sample_t *in, uint8_t n_phases)
{
    const fault_monitor_config_t *c = &m->cfg;
    /* the backend's own verdicts first: they are facts, not estimates */
    if ((in->status & HAL_STATUS_PWM_TRIP) != 0u) {
        return DRIVE_FAULT_HW_TRIP;
    }
    if ((in->status & HAL_STATUS_ADC_FAULT) != 0u) {
        return DRIVE_FAULT_ADC;
    }
    /* overruns: a leaky level, so isolated ones are tolerated and a burst
     * (overrun_limit / overrun_weight of them within about overrun_weight
     * samples each) trips; every sample without one leaks 1, whatever
     * other status it carries (HAL_STATUS_BUS_INVALID is no overrun) */
    if ((in->status & HAL_STATUS_OVERRUN) != 0u) {
        m->overruns += 1u;
        m->overrun_level += c->overrun_weight;
        if (m->overrun_level >= c->overrun_limit) {
            return DRIVE_FAULT_OVERRUN;
        }
    } else if (m->overrun_level > 0) {
        m->overrun_level -= 1;
    }
    bool at_rail = false;
    bool over = false;
    mc_t i2 = MC_ZERO;
    for (uint8_t k = 0; k < n_phases && k < HAL_MAX_PHASES; ++k) {
        const mc_t i = in->i_A[k];
        const mc_t a = mc_abs(i);
        if (!mc_lt(a, c->i_trip_A)) {
            /* at or beyond the trip, or not a number (NaN compares false,
             * inf is not below any trip): the non-finite sample is tested
             * only here, the common path makes one comparison for both */
            if (!mc_is_finite(i)) {
                return DRIVE_FAULT_NON_FINITE;
            }
            if (mc_gt(a, c->i_trip_A)) {
                /* the i_trip_samples-th sample in a row beyond the trip (the
                 * first one when it is 1: the instantaneous trip) */
                if (m->oc_run + 1 >= c->i_trip_samples) {
                    return DRIVE_FAULT_OVERCURRENT;
                }
                over = true;
            }
        }
        /* rail_abs_A is MC_MAX when the rail is unknown (never reached) */
        at_rail = at_rail || mc_ge(a, m->rail_abs_A);
        /* stuck: bit-identical samples while the voltage across the phase
         * moved by stuck_dv_V (di/dt = dv/L makes any live current move) */
        if (mc_eq(i, m->i_last_A[k])) {
            if (m->same_run[k] == 0) { /* a run starts: the command range from here */
                m->v_lo_V[k] = m->v_last_V[k];
                m->v_hi_V[k] = m->v_last_V[k];
            }
            m->same_run[k] += 1;
            m->v_lo_V[k] = mc_min(m->v_lo_V[k], m->v_last_V[k]);
            m->v_hi_V[k] = mc_max(m->v_hi_V[k], m->v_last_V[k]);
            if (m->same_run[k] >= c->stuck_ticks && mc_ge(mc_sub(m->v_hi_V[k], m->v_lo_V[k]), c->stuck_dv_V)) {
                return DRIVE_FAULT_SENSOR_STUCK;
            }
        } else {
            m->i_last_A[k] = i;
            m->same_run[k] = 0;
        }
    }
    m->oc_run = over ? m->oc_run + 1 : 0;
    m->rail_run = at_rail ? m->rail_run + 1 : 0;
    if (m->rail_run >= c->rail_ticks && at_rail) {
        return DRIVE_FAULT_SENSOR_RAIL;
    }
    if (!mc_is_finite(in->v_bus_V)) {
        return DRIVE_FAULT_NON_FINITE;
    }
    /* I^2 t on the current vector: three phases carry 3/2 |i_ab|^2 in the
     * sum of squares, two carry |i_ab|^2; the design scales i2t_cont_A2 to
     * the same sum (design/paper000_design.c). Heating is slow against a
     * sample: every FAULT_I2T_SUBSAMPLE-th sample enters the block's mean. */
    m->i2_n += 1;
    if ((m->i2_n & (FAULT_I2T_SUBSAMPLE - 1)) == 0) {
        for (uint8_t k = 0; k < n_phases && k < HAL_MAX_PHASES; ++k) {
            i2 = mc_mac(i2, in->i_A[k], in->i_A[k]);
        }
        m->i2_sum_A2 = mc_add(m->i2_sum_A2, i2);
    }
    if (m->i2_n >= FAULT_I2T_DECIMATION) {
        const mc_t excess =
            mc_sub(mc_div_i(m->i2_sum_A2, FAULT_I2T_DECIMATION / FAULT_I2T_SUBSAMPLE), c->i2t_cont_A2);
        m->i2t_A2 = mc_max(MC_ZERO, mc_mac(m->i2t_A2, excess, c->i2t_gain));
        m->i2_sum_A2 = MC_ZERO;
        m->i2_n = 0;
        if (mc_gt(m->i2t_A2, c->i2t_limit_A2)) {
            return DRIVE_FAULT_I2T;
        }
    }
    return DRIVE_FAULT_NONE;
}

drive_fault_t fault_monitor_command(fault_monitor_t *m, const hal_command_t *out, bool saturated)
{
    for (uint8_t k = 0; k < out->n_phases && k < HAL_MAX_PHASES; ++k) {
        if (!mc_is_finite(out->v_V[k])) {
            return DRIVE_FAULT_NON_FINITE;
        }
        m->v_last_V[k] = out->v_V[k];
    }
    m->sat_run = saturated ? m->sat_run + 1 : 0;
    if (m->sat_run > m->cfg.sat_max_ticks) {
        return DRIVE_FAULT_VOLTAGE_SATURATION;
    }
    return DRIVE_FAULT_NONE;
}

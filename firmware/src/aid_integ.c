/* Integrity monitor of an aiding source (aid_integ.h): the window of test
 * statistics, its chi-square band and the OK / SUSPECT / ISOLATED ladder. */
#include "ggins/aid_integ.h"

#include <stddef.h>

#include "ggins/ggmath.h"

/* Upper quantile of chi^2(k) at the standard-normal z (Wilson & Hilferty 1931). */
static double wh_quantile(double k, double z)
{
    const double c = 2.0 / (9.0 * k);
    double b = (1.0 - c) + (z * gg_sqrt_d(c));
    if (b < 0.0) {
        b = 0.0;
    }
    return k * b * b * b;
}

gg_status_t gg_integ_init(gg_integ_t *m, const gg_integ_config_t *cfg, double dof)
{
    gg_integ_config_t c;
    int32_t i;
    if ((m == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    c = *cfg;
    if (c.window == 0) {
        c.window = GG_INTEG_WINDOW_DEFAULT;
    }
    if (c.z == 0.0) {
        c.z = GG_INTEG_Z_DEFAULT;
    }
    if (c.isolate_after == 0) {
        c.isolate_after = GG_INTEG_ISOLATE_AFTER_DEFAULT;
    }
    if (c.recover_after == 0) {
        c.recover_after = GG_INTEG_RECOVER_AFTER_DEFAULT;
    }
    if (((c.enable != 0) && (c.enable != 1)) || (c.window < 1) || (c.window > GG_INTEG_WINDOW_MAX) ||
        !(c.z >= 1.0) || !(c.z <= 10.0) || (c.isolate_after < 1) || (c.isolate_after > 1000) ||
        (c.recover_after < 1) || (c.recover_after > 1000) || !(dof > 0.0) || !(dof <= 100.0)) {
        return GG_ERR_CONFIG;
    }
    m->cfg = c;
    m->dof = dof;
    for (i = 0; i < GG_INTEG_WINDOW_MAX; ++i) {
        m->ring[i] = 0.0;
        m->band[i] = wh_quantile(dof * ((double)i + 1.0), c.z);
    }
    m->n = 0;
    m->head = 0;
    m->state = GG_INTEG_OK;
    m->run_out = 0;
    m->run_in = 0;
    m->ratio = 0.0;
    m->last_stat = 0.0;
    m->n_tests = 0U;
    m->n_outside = 0U;
    m->n_suspect = 0U;
    m->n_isolated = 0U;
    m->initialized = 1;
    return GG_OK;
}

/* One rung of the ladder after a window outside (out = 1) or inside its band. */
static void integ_ladder(gg_integ_t *m, int out)
{
    if (out != 0) {
        m->run_out++;
        m->run_in = 0;
        m->n_outside++;
        if (m->state == GG_INTEG_OK) {
            m->state = GG_INTEG_SUSPECT;
            m->n_suspect++;
            m->run_out = 0; /* isolate_after windows outside from here on */
        } else if ((m->state == GG_INTEG_SUSPECT) && (m->run_out >= m->cfg.isolate_after)) {
            m->state = GG_INTEG_ISOLATED;
            m->n_isolated++;
            m->run_out = 0;
        } else {
            /* ISOLATED stays */
        }
    } else {
        m->run_in++;
        m->run_out = 0;
        if ((m->state != GG_INTEG_OK) && (m->run_in >= m->cfg.recover_after)) {
            if (m->state == GG_INTEG_ISOLATED) {
                m->state = GG_INTEG_SUSPECT;
            } else {
                m->state = GG_INTEG_OK;
            }
            m->run_in = 0;
        }
    }
}

gg_status_t gg_integ_test(gg_integ_t *m, double stat)
{
    double s = stat;
    double sum = 0.0;
    int32_t i;
    if (m == NULL) {
        return GG_ERR_NULL;
    }
    if (m->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!(s >= 0.0) || !(s <= GG_INTEG_STAT_MAX)) {
        s = GG_INTEG_STAT_MAX;
    }
    m->last_stat = s;
    m->n_tests++;
    m->ring[m->head] = s;
    m->head++;
    if (m->head >= m->cfg.window) {
        m->head = 0;
    }
    if (m->n < m->cfg.window) {
        m->n++;
    }
    for (i = 0; i < m->n; ++i) {
        sum += m->ring[i];
    }
    m->ratio = sum / m->band[m->n - 1];
    if (m->cfg.enable == 0) {
        m->state = GG_INTEG_OK;
        return GG_OK;
    }
    integ_ladder(m, (m->ratio > 1.0) ? 1 : 0);
    return GG_OK;
}

/* Round-trip check of the C emitter: the generated file (compiled into this program) must hold
 * exactly the struct dtc_config_from_si() produces from the defaults, field by field. */
#include <stdio.h>
#include <string.h>

#include "dtc_config_si.h"

extern const dtc_config_t dtc_config_default;

int main(void)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    char msg[256];
    int bad = 0;

    dtc_config_si_defaults(&si);
    if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
        fprintf(stderr, "defaults refused: %s\n", msg);
        return 1;
    }
#define CHK(f) do { if (cfg.f != dtc_config_default.f) { fprintf(stderr, "field %s differs\n", #f); bad = 1; } } while (0)
    CHK(version); CHK(topology); CHK(estimator); CHK(compensation); CHK(sstp_table); CHK(mode);
    CHK(fstp_vmid_measured); CHK(v_base_mv); CHK(i_base_ma); CHK(w_base_mrad_s); CHK(pole_pairs);
    CHK(rs_iq); CHK(ls_iq); CHK(psi_m_iq); CHK(k_in_q31); CHK(k_leak_q31); CHK(enc_counts);
    CHK(enc_gain_q16); CHK(enc_offset); CHK(v_f_iq); CHK(v_ce_iq); CHK(v_d_iq); CHK(r_on_iq);
    CHK(flux_band_iq); CHK(torque_band_iq); CHK(speed_div); CHK(speed_k_iq); CHK(speed_min_counts); CHK(stall_speed_periods);
    CHK(kp_iq); CHK(ki_ts_iq); CHK(torque_limit_iq); CHK(torque_trim_k_q15); CHK(speed_limit_iq); CHK(flux_ref_iq);
    CHK(speed_ref_iq); CHK(torque_ref_iq); CHK(adc_i_gain_iq); CHK(adc_i_offset[0]);
    CHK(adc_i_offset[1]); CHK(adc_i_offset[2]); CHK(adc_vdc_gain_iq); CHK(adc_vdc_offset);
    CHK(adc_vmid_gain_iq); CHK(adc_vmid_offset); CHK(i_trip_iq); CHK(vdc_max_iq); CHK(vdc_min_iq);
    CHK(i_lim_iq); CHK(polarity_mid); CHK(vmid_cal); CHK(lpf_comp); CHK(wc_pu_iq); CHK(lpf_wmin_iq); CHK(dc_supp); CHK(dcs_k_iq); CHK(vmid_g_iq);
    if (dtc_config_validate(&dtc_config_default) != DTC_OK) {
        fprintf(stderr, "generated configuration refused by dtc_config_validate\n");
        bad = 1;
    }
    if (!bad) {
        printf("emitted configuration matches the converter, field by field\n");
    }
    return bad;
}

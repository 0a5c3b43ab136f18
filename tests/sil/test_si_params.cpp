// The description of the converter's SI inputs (tools/config/dtc_si_params.h) checked against what
// is derived from it: the converter enforces every row's plain range with that row's error code
// and member; the firmware.* scenario keys are the belief rows with their unit and range; every
// key a row names is a scenario key; the docs' table is the description's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <set>
#include <string>

extern "C" {
#include "dtc_config_si.h"
#include "dtc_config_si_conv.h"
#include "dtc_si_params.h"
}

#include "scenario.hpp"

namespace {

/// A configuration the converter accepts in which the row's value is checked: the PM rig for
/// the rows of the PM laws, else the IM rig under the row's first law, with the row's switch set.
dtc_config_si_t base_for(const dtc_si_param_t& p)
{
    dtc_config_si_t si;
    if ((p.laws & DTC_SIP_LAW(DTC_LAW_PM_DTC)) != 0U) {
        dtc_config_si_defaults(&si);
    } else {
        dtc_config_si_im_defaults(&si);
        int law = DTC_LAW_IM_DTC;
        while ((p.laws & DTC_SIP_LAW(static_cast<unsigned>(law))) == 0U) {
            ++law;
        }
        si.law = law;
        si.psir_ref_wb = 0.5; // the SVM laws take the rotor-flux command
    }
    si.relay_delay_s = 0.01; // a valid closing time, should the row switch the relay on
    switch (p.when) {
    case DTC_SIP_IF_HANDOVER_GIVEN: si.handover_auto = 0; break;
    case DTC_SIP_IF_ILIM_GIVEN: si.current_limit_auto = 0; break;
    case DTC_SIP_IF_PI_BW: si.pi_from_bandwidth = 1; break;
    case DTC_SIP_IF_PI_GAINS: si.pi_from_bandwidth = 0; break;
    case DTC_SIP_IF_RELAY: si.reconfig_relay = 1; break;
    default: break;
    }
    return si;
}

void set_value(const dtc_si_param_t& p, dtc_config_si_t* si, double v)
{
    char* at = reinterpret_cast<char*>(si) + p.offset;
    if (p.type == DTC_SIP_DOUBLE) {
        std::memcpy(at, &v, sizeof v);
    } else {
        const int i = static_cast<int>(v);
        std::memcpy(at + (p.type == DTC_SIP_INT3 ? sizeof(int) : 0U), &i, sizeof i); // int[3]: element 1
    }
}

std::string range_text(const dtc_si_param_t& p)
{
    char buf[64];
    return dtc_si_param_range_text(&p, buf, sizeof buf);
}

} // namespace

TEST(SiParams, EveryRowsRangeIsEnforcedByTheConverterWithItsCodeAndMember)
{
    const double inf = std::numeric_limits<double>::infinity();
    ASSERT_GT(dtc_si_param_count, 80u);
    for (std::size_t i = 0; i < dtc_si_param_count; ++i) {
        const dtc_si_param_t& p = dtc_si_params[i];
        SCOPED_TRACE(p.name);
        dtc_config_si_t si = base_for(p);
        dtc_config_t cfg;
        dtc_si_error_t e;
        ASSERT_EQ(dtc_config_from_si_err(&si, &cfg, &e), DTC_SI_OK) << e.msg;
        ASSERT_TRUE(dtc_si_param_applies(&p, &si));
        const bool integer = p.type != DTC_SIP_DOUBLE;
        const bool lo_open = p.bounds == DTC_SIP_LO_OPEN || p.bounds == DTC_SIP_OPEN;
        const bool hi_open = p.bounds == DTC_SIP_HI_OPEN || p.bounds == DTC_SIP_OPEN;
        // just outside each finite end (an integer one below or above; NaN for "any finite value")
        std::vector<double> outside, inside;
        if (p.bounds == DTC_SIP_ANY) {
            if (!integer) {
                outside.push_back(std::nan(""));
            }
        } else {
            if (p.lo > -DTC_SIP_INF) {
                outside.push_back(integer ? p.lo - 1.0 : lo_open ? p.lo : std::nextafter(p.lo, -inf));
                inside.push_back(integer || !lo_open ? p.lo : std::nextafter(p.lo, inf));
            }
            if (p.hi < DTC_SIP_INF) {
                outside.push_back(integer ? p.hi + 1.0 : hi_open ? p.hi : std::nextafter(p.hi, inf));
                inside.push_back(integer || !hi_open ? p.hi : std::nextafter(p.hi, -inf));
            }
        }
        if (p.bounds != DTC_SIP_ANY) {
            EXPECT_FALSE(outside.empty()) << "a range with no finite end checks nothing";
        }
        for (const double v : outside) {
            dtc_config_si_t bad = si;
            set_value(p, &bad, v);
            EXPECT_EQ(dtc_config_from_si_err(&bad, &cfg, &e), p.err) << v << ": " << e.msg;
            EXPECT_STREQ(e.field, p.name) << v << ": " << e.msg;
            EXPECT_NE(std::string(e.msg).find(p.name), std::string::npos) << e.msg;
        }
        for (const double v : inside) {
            dtc_config_si_t good = si;
            set_value(p, &good, v);
            char msg[256] = "";
            dtc_si_conv_t c = {msg, sizeof msg, DTC_SI_OK, ""};
            EXPECT_EQ(dtc_si_params_check(&c, &good), DTC_SI_OK) << v << ": " << msg;
        }
    }
}

TEST(SiParams, AConverterRefusalCarriesTheMemberAndARowNamesOnlyScenarioKeys)
{
    // a relation between members (not a plain range) also names its member
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    si.dead_time_s = si.ts_s;
    dtc_config_t cfg;
    dtc_si_error_t e;
    EXPECT_EQ(dtc_config_from_si_err(&si, &cfg, &e), DTC_SI_ERR_DEADTIME);
    EXPECT_STREQ(e.field, "dead_time_s");
    // the message-only form gives the same refusal
    char msg[256];
    EXPECT_EQ(dtc_config_from_si(&si, &cfg, msg, sizeof msg), DTC_SI_ERR_DEADTIME);
    EXPECT_STREQ(msg, e.msg);
    // a Q-format overflow names the member its value came from
    dtc_config_si_defaults(&si);
    si.rs_ohm = 1e6;
    EXPECT_EQ(dtc_config_from_si_err(&si, &cfg, &e), DTC_SI_ERR_RANGE);
    EXPECT_STREQ(e.field, "rs_ohm");

    const auto keys = sil::scenario_keys();
    auto is_key = [&](const std::string& k) {
        for (const auto& d : keys) {
            if (d.name == k) {
                return true;
            }
        }
        return false;
    };
    for (std::size_t i = 0; i < dtc_si_param_count; ++i) {
        const dtc_si_param_t& p = dtc_si_params[i];
        SCOPED_TRACE(p.name);
        EXPECT_EQ(dtc_si_param_find(p.name), &p);
        // every dotted word of the keys column is a scenario key, and a row with keys has one
        const std::string text = std::string(p.keys) + " ";
        std::string word;
        int n = 0;
        for (const char ch : text) {
            if ((ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '.') {
                word += ch;
                continue;
            }
            if (word.find('.') != std::string::npos && word.back() != '.') {
                EXPECT_TRUE(is_key(word)) << word << " is not a scenario key";
            }
            n += is_key(word) ? 1 : 0;
            word.clear();
        }
        EXPECT_EQ(n > 0, p.keys[0] != '\0') << p.keys;
    }
}

TEST(SiParams, TheFirmwareScenarioKeysAreTheBeliefRows)
{
    int beliefs = 0;
    const auto keys = sil::scenario_keys();
    for (std::size_t i = 0; i < dtc_si_param_count; ++i) {
        const dtc_si_param_t& p = dtc_si_params[i];
        if (p.belief == nullptr) {
            continue;
        }
        ++beliefs;
        SCOPED_TRACE(p.name);
        EXPECT_EQ(p.type, DTC_SIP_DOUBLE);
        bool found = false;
        for (const auto& k : keys) {
            if (k.name == std::string("firmware.") + p.name) {
                found = true;
                EXPECT_EQ(k.unit, p.unit);
                EXPECT_EQ(k.range, range_text(p));
                EXPECT_NE(k.doc.find(std::string("not given: ") + p.belief), std::string::npos) << k.doc;
            }
        }
        EXPECT_TRUE(found);
    }
    // Every other firmware.* key is one of the machine's sensors or its mechanics as the firmware
    // believes them, which dtc-sil identify writes (tools/sil/src/firmware_si.cpp reads them), or the
    // board data's encoder line count (a wrong one): not a converter member with a plant fallback.
    static const std::set<std::string> sensors = {"firmware.pole_pairs",       "firmware.encoder_offset_rad",
                                                  "firmware.encoder_reversed", "firmware.j_kgm2",
                                                  "firmware.b_nm_s_per_rad",   "firmware.coulomb_nm",
                                                  "firmware.encoder_lines"};
    int firmware_keys = 0;
    for (const auto& k : keys) {
        firmware_keys += k.name.rfind("firmware.", 0) == 0 && sensors.count(k.name) == 0 ? 1 : 0;
    }
    EXPECT_EQ(firmware_keys, beliefs);
    EXPECT_EQ(beliefs, 12); // rs, ls, lq, psi_m, rr, lls, llr, lm, v_ce, v_d, r_on, dead time
}

TEST(SiParams, TheDocsTableIsTheDescriptions)
{
    std::ifstream f(std::string(DTC_SOURCE_DIR) + "/docs/sil.md");
    ASSERT_TRUE(f.good());
    std::stringstream ss;
    ss << f.rdbuf();
    char* buf = nullptr;
    std::size_t n = 0;
    std::FILE* mem = open_memstream(&buf, &n);
    ASSERT_NE(mem, nullptr);
    ASSERT_EQ(dtc_si_params_markdown(mem), 0);
    std::fclose(mem);
    const std::string table(buf, n);
    std::free(buf);
    EXPECT_NE(ss.str().find("<!-- si-params:begin -->\n" + table + "<!-- si-params:end -->"), std::string::npos)
        << "docs/sil.md's SI parameter table is stale: run build/host/bin/dtc_si_params_doc --write docs/sil.md";
}

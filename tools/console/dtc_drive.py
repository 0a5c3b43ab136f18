"""dtc_drive - talk to the DTC drive over its serial line (docs/operate.md), for scripts and for
the console (dtc_console.py).

The frames, command ids, payload layouts, error codes, capture quantities and fault names are
read from the firmware's own headers (firmware/comm/proto.h, capture.h, firmware/app/app_fault.h,
app_core.h), so this module and the firmware cannot disagree on a number.

    from dtc_drive import Drive
    with Drive("/tmp/dtc0") as d:
        d.arm(); d.speed(1000.0); print(d.status()["speed_rpm"])

Values are SI (rpm, N*m, Wb, A, V, s) at this interface; the per-unit raw values of the wire are
converted with the bases the drive reports in HELLO (dtc_base.h).
"""

import binascii
import math
import os
import re
import struct
import time

import serial

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SOF = 0xA5
IQ_ONE = float(1 << 24)


def _read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
        return f.read()


def _enum(text, prefix, block=None):
    """{NAME: value} of the enumerators PREFIX_NAME = value in a C header's text (within
    `enum block { ... }` if given)."""
    if block is not None:
        text = re.search(r"enum %s \{(.*?)\};" % block, text, re.S).group(1)
    return {m.group(1): int(m.group(2), 0) for m in re.finditer(r"\b%s(\w+)\s*=\s*(0x[0-9A-Fa-f]+|\d+)" % prefix, text)}


_PROTO = _read("firmware/comm/proto.h")
_CAPTURE = _read("firmware/comm/capture.h")
_FAULT = _read("firmware/app/app_fault.h")
_CORE = _read("firmware/app/app_core.h")
_IDENT = _read("firmware/app/app_ident.h")

CMD = _enum(_PROTO, "PROTO_", "proto_cmd")
ERR = _enum(_PROTO, "PROTO_ERR_")
REFUSAL = _enum(_PROTO, "PROTO_REFUSE_")
QUANTITY = _enum(_CAPTURE, "CAPTURE_Q_")
TRIGGER = _enum(_CAPTURE, "CAPTURE_TRIG_")
CAPTURE_STATE = {"OFF": 0, "DONE": 1, "ARMED": 2, "TRIGGERED": 3}
STATE = {v: k.lower() for k, v in _enum(_CORE, "APP_STATE_").items()}
IDENT_SUB = _enum(_PROTO, "PROTO_IDENT_", "proto_ident_sub")
IDENT_STEP = {v: k.lower() for k, v in _enum(_IDENT, "APP_IDENT_", "app_ident_step").items()}
IDENT_FAIL = {v: k.lower() for k, v in _enum(_IDENT, "APP_IDENT_FAIL_", "app_ident_fail").items()}
APPLY_ERR = {v: k.lower() for k, v in _enum(_IDENT, "APP_IDENT_APPLY_", "app_ident_apply_err").items()}
# The rows IDENT_APPLY writes (firmware/app/app_ident_apply.c): on both machines, then on a PM DTC
# configuration, then on an induction machine's (the DFOC's four rows on the DFOC law only, the
# DSVM's band on the DSVM law only).
_IDENT_APPLY_COMMON = ["machine.rs_iq", "machine.pole_pairs", "board.enc_gain_q16", "board.enc_reversed",
                       "board.td_ts_q15", "speed.kp_iq", "speed.ki_ts_iq", "prot.enc_freeze_speed_iq"]
IDENT_APPLY_ROWS = _IDENT_APPLY_COMMON + ["u.pm_dtc.machine.ls_iq", "u.pm_dtc.machine.inv_ls_iq",
                                          "u.pm_dtc.machine.lq_iq",
                                          "u.pm_dtc.machine.psi_m_iq", "board.enc_offset"]
IDENT_APPLY_ROWS_IM = _IDENT_APPLY_COMMON + [
    "u.im.machine.rr_iq", "u.im.machine.sigma_ls_iq", "u.im.machine.sigma_lr_iq", "u.im.machine.kr_iq",
    "u.im.machine.ks_iq", "u.im.machine.inv_ks_iq", "u.im.machine.m_iq", "u.im.fw.kt_iq",
    "u.im.ref.inv_psir_sq_iq", "u.im.ref.magn_ramp_iq", "u.im.ref.magn_k_q31", "u.im.ref.magn_periods",
    "u.im.ref.enc_plaus_iq", "prot.i_lim_iq", "speed.torque_limit_iq", "speed.torque_ref_iq"]
IDENT_APPLY_ROWS_DFOC = IDENT_APPLY_ROWS_IM + ["u.im.dfoc.id_ref_iq", "u.im.dfoc.iq_per_t_iq", "u.im.dfoc.kp_iq",
                                              "u.im.dfoc.ki_ts_iq"]
IDENT_APPLY_ROWS_DSVM = IDENT_APPLY_ROWS_IM + ["u.im.dsvm.torque_band2_iq"]
LAW = _enum(_read("firmware/dtc/dtc_config_common.h"), "DTC_LAW_", "dtc_law")
IDENT_QUANTITY = {v: k.lower() for k, v in _enum(_IDENT, "APP_IDENT_Q_", "app_ident_quantity").items()}
FAULT = {int(m.group(2)): (m.group(3), m.group(1)) for m in
         re.finditer(r'X\((\w+), (\d+), "(\w+)", (\w+),', _FAULT)}
PARAM_FLAG_RO = 0x0001
PARAM_FLAG_DISARMED_ONLY = 0x0002

# The capture quantities under the SIL trace's column names (capture.h), and the base each is
# scaled by (None: an integer, sector or vector).
CHANNEL = {
    "i_a_a": ("I_A", "i"), "i_b_a": ("I_B", "i"), "i_c_a": ("I_C", "i"),
    "psi_alpha_est_wb": ("PSI_ALPHA_EST", "psi"), "psi_beta_est_wb": ("PSI_BETA_EST", "psi"),
    "torque_est_nm": ("TORQUE_EST", "t"), "speed_rpm": ("SPEED", "rpm"),
    "speed_ref_rpm": ("SPEED_REF", "rpm"), "torque_ref_nm": ("TORQUE_REF", "t"),
    "psi_ref_wb": ("PSI_REF", "psi"), "vdc_v": ("VDC", "v"), "vmid_v": ("VMID", "v"),
    "sector": ("SECTOR", None), "vector": ("VECTOR", None),
}


class DriveError(RuntimeError):
    """The drive refused a request (code, detail) or did not answer."""

    def __init__(self, msg, code=None, detail=None):
        super().__init__(msg)
        self.code = code
        self.detail = detail


def crc16(data):
    """CRC-16/CCITT-FALSE (crc16.h)."""
    return binascii.crc_hqx(bytes(data), 0xFFFF)


def encode(cmd, seq, payload=b""):
    body = bytes([len(payload), cmd & 0xFF, seq & 0xFF]) + bytes(payload)
    c = crc16(body)
    return bytes([SOF]) + body + bytes([c >> 8, c & 0xFF])


class Decoder:
    """Frames out of a byte stream, resynchronising after garbage and bad CRCs (frame.h)."""

    def __init__(self):
        self.buf = bytearray()

    def feed(self, data):
        self.buf += data
        out = []
        while True:
            i = self.buf.find(bytes([SOF]))
            if i < 0:
                self.buf.clear()
                return out
            del self.buf[:i]
            if len(self.buf) < 6:
                return out
            n = self.buf[1]
            if n > 120:
                del self.buf[:1]
                continue
            if len(self.buf) < n + 6:
                return out
            body = bytes(self.buf[1:4 + n])
            rx = (self.buf[4 + n] << 8) | self.buf[5 + n]
            if crc16(body) != rx:
                del self.buf[:1]
                continue
            out.append((body[1], body[2], body[3:]))
            del self.buf[:6 + n]


def _err_text(req, code, detail):
    name = {v: k for k, v in ERR.items()}.get(code, str(code)).lower()
    why = ""
    if code == ERR.get("REFUSED"):
        why = " (%s)" % {v: k for k, v in REFUSAL.items()}.get(detail, str(detail)).lower()
    elif code == ERR.get("STORE"):
        why = " (store status %d)" % detail
    elif detail:
        why = " (detail %d)" % detail
    cmd = {v: k for k, v in CMD.items()}.get(req, "0x%02x" % req)
    return "the drive refused %s: %s%s" % (cmd.lower(), name, why)


class Drive:
    def __init__(self, port, baud=115200, timeout_s=1.0, retries=3):
        self.port = port
        try:
            self.ser = serial.Serial(port, baud, timeout=0.01)
        except (serial.SerialException, OSError) as e:
            raise DriveError("cannot open %s: %s" % (port, e)) from e
        self.timeout_s = timeout_s
        self.retries = retries
        self.seq = 0
        self.dec = Decoder()
        self.info = None
        self._params = None

    def close(self):
        self.ser.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # ---- transport --------------------------------------------------------------------------
    def request(self, cmd, payload=b""):
        """One request, its answer's payload; DriveError on an error frame or no answer."""
        for _ in range(self.retries):
            self.seq = (self.seq + 1) & 0xFF
            self.ser.write(encode(cmd, self.seq, payload))
            self.ser.flush()
            end = time.monotonic() + self.timeout_s
            while time.monotonic() < end:
                for rcmd, rseq, pl in self.dec.feed(self.ser.read(256)):
                    if rseq != self.seq or rcmd == CMD["TELEMETRY"]:
                        continue
                    if rcmd == CMD["ERROR"]:
                        req, code, detail = struct.unpack_from("<HHh", pl)
                        raise DriveError(_err_text(req, code, detail), code, detail)
                    if rcmd == (cmd | 0x80):
                        return bytes(pl)
        raise DriveError("no answer from the drive on %s (%d tries of %.1f s)" % (self.port, self.retries, self.timeout_s))

    # ---- units ------------------------------------------------------------------------------
    def hello(self):
        pl = self.request(CMD["HELLO"])
        f = struct.unpack_from("<HHIHHIHHHHH", pl)
        keys = ("proto_version", "firmware_version", "param_table_hash", "param_count", "law",
                "isr_period_ns", "iq_q", "capture_buf_words32", "capture_channels_max",
                "frame_max_payload", "faultlog_entries")
        info = dict(zip(keys, f))
        v, i, w, p = struct.unpack_from("<IIIH", pl, 26)
        info.update(v_base_v=v / 1000.0, i_base_a=i / 1000.0, w_base_rad_s=w / 1000.0, pole_pairs=p)
        self.info = info
        return info

    def bases(self):
        """SI per pu: v, i, psi, t (torque), rpm (mechanical speed) and w (electrical rad/s)."""
        if self.info is None:
            self.hello()
        h = self.info
        psi = h["v_base_v"] / h["w_base_rad_s"]
        p = max(1, h["pole_pairs"])
        return self._derived({"v": h["v_base_v"], "i": h["i_base_a"], "psi": psi, "w": h["w_base_rad_s"],
                "t": 1.5 * p * psi * h["i_base_a"], "rpm": h["w_base_rad_s"] / p * 60.0 / (2.0 * math.pi),
                "s": 1.0 / h["w_base_rad_s"], "z": h["v_base_v"] / h["i_base_a"],
                "l": h["v_base_v"] / h["i_base_a"] / h["w_base_rad_s"], "one": 1.0, "turn": 2.0 * math.pi,
                "milli": 1e-3})

    def _derived(self, b):
        b["inv_l"] = 1.0 / b["l"]
        b["inv_psi"] = 1.0 / b["psi"]
        b["t_w"] = b["t"] / b["w"]
        return b

    def si(self, raw, base):
        return raw / IQ_ONE * self.bases()[base]

    def raw(self, value, base):
        r = int(round(value / self.bases()[base] * IQ_ONE))
        return max(-(1 << 31), min((1 << 31) - 1, r))

    # ---- commands ---------------------------------------------------------------------------
    def status(self):
        pl = self.request(CMD["STATUS"])
        (state, armed, fault, detail, tick, speed, speed_ref, te, te_ref, psi, vdc, vmid, mode, nflt, rxf,
         rxc) = struct.unpack_from("<HHHhIiiiiiiiHHHH", pl)
        return {
            "state": STATE.get(state, str(state)), "armed": bool(armed),
            "fault": FAULT.get(fault, ("fault_%d" % fault, ""))[0], "fault_detail": detail, "tick": tick,
            "speed_rpm": self.si(speed, "rpm"), "speed_ref_rpm": self.si(speed_ref, "rpm"),
            "torque_est_nm": self.si(te, "t"), "torque_ref_nm": self.si(te_ref, "t"),
            "flux_est_wb": self.si(psi, "psi"), "vdc_v": self.si(vdc, "v"), "vmid_v": self.si(vmid, "v"),
            "mode": "torque" if mode == 1 else "speed", "faults_recorded": nflt,
            "rx_frames": rxf, "rx_crc_errors": rxc,
        }

    def arm(self):
        self.request(CMD["ARM"])

    def disarm(self):
        self.request(CMD["DISARM"])

    def speed(self, rpm):
        self.request(CMD["SPEED_REF"], struct.pack("<i", self.raw(rpm, "rpm")))

    def torque(self, nm):
        self.request(CMD["TORQUE_REF"], struct.pack("<i", self.raw(nm, "t")))

    def clear(self):
        self.request(CMD["FAULT_CLEAR"])

    def faults(self):
        """The fault log, newest first: reason, detail, tick and the snapshot (SI)."""
        out = []
        n = self.info["faultlog_entries"] if self.info else 8
        for k in range(n):
            try:
                pl = self.request(CMD["FAULTLOG_READ"], struct.pack("<H", k))
            except DriveError as e:
                if e.code == ERR["RANGE"]:
                    break
                raise
            (_, _, tick, reason, detail, ia, ib, ic, vdc, vmid, speed, pa, pb, te, te_ref, sref, sector, vector,
             state) = struct.unpack_from("<HHIHhiiiiiiiiiiiHHH", pl)
            out.append({
                "reason": FAULT.get(reason, ("fault_%d" % reason, ""))[0], "detail": detail, "tick": tick,
                "snapshot": {
                    "i_a_a": self.si(ia, "i"), "i_b_a": self.si(ib, "i"), "i_c_a": self.si(ic, "i"),
                    "vdc_v": self.si(vdc, "v"), "vmid_v": self.si(vmid, "v"), "speed_rpm": self.si(speed, "rpm"),
                    "psi_alpha_est_wb": self.si(pa, "psi"), "psi_beta_est_wb": self.si(pb, "psi"),
                    "torque_est_nm": self.si(te, "t"), "torque_ref_nm": self.si(te_ref, "t"),
                    "speed_ref_rpm": self.si(sref, "rpm"), "sector": sector, "vector": vector,
                    "state": STATE.get(state, str(state)),
                },
            })
        return out

    def telemetry(self, channels, decim, n, timeout_s=5.0):
        """Starts the telemetry stream of up to 4 channels (capture names), collects n frames and
        stops it: (decim in force, [(tick, {channel: SI value})])."""
        qs = [QUANTITY[CHANNEL[c][0]] for c in channels]
        pl = self.request(CMD["TELEMETRY_START"], struct.pack("<HH%dH" % len(qs), decim, len(qs), *qs))
        (got,) = struct.unpack_from("<H", pl)
        out = []
        end = time.monotonic() + timeout_s
        while len(out) < n and time.monotonic() < end:
            for rcmd, rseq, pl in self.dec.feed(self.ser.read(256)):
                if rcmd != CMD["TELEMETRY"] or rseq != self.seq:
                    continue
                tick = struct.unpack_from("<I", pl)[0]
                vals = struct.unpack_from("<%di" % len(qs), pl, 4)
                out.append((tick, {c: (v if CHANNEL[c][1] is None else self.si(v, CHANNEL[c][1]))
                                   for c, v in zip(channels, vals)}))
        self.request(CMD["TELEMETRY_STOP"])
        return got, out[:n]

    # ---- capture ----------------------------------------------------------------------------
    def capture(self, channels, samples, trigger="now", pre=0, decim=1, timeout_s=30.0):
        """Sets up a capture, waits for it and reads it out: (ticks, {channel: [SI values]}).
        trigger: now | fault | above:CH:LEVEL | below:CH:LEVEL | rising:CH:LEVEL | falling:CH:LEVEL
        (CH one of the channels, LEVEL in its SI unit)."""
        for c in channels:
            if c not in CHANNEL:
                raise DriveError("capture: unknown channel %r (one of %s)" % (c, ", ".join(CHANNEL)))
        if not 1 <= len(channels) <= 4:
            raise DriveError("capture: 1 to 4 channels")
        parts = trigger.split(":")
        kind = parts[0].upper()
        if kind not in TRIGGER or kind == "COUNT" or (kind in ("NOW", "FAULT")) != (len(parts) == 1) or \
                (len(parts) not in (1, 3)):
            raise DriveError("capture: bad --trigger %r (now, fault, or above|below|rising|falling:CHANNEL:LEVEL)"
                             % trigger)
        tch, level = 0, 0
        if len(parts) == 3:
            if parts[1] not in channels:
                raise DriveError("capture: trigger channel %r is not among --channels" % parts[1])
            tch = channels.index(parts[1])
            base = CHANNEL[parts[1]][1]
            level = int(float(parts[2])) if base is None else self.raw(float(parts[2]), base)
        if self.info is None:
            self.hello()
        depth = self.info["capture_buf_words32"]
        if samples < 1 or samples * len(channels) > depth:
            raise DriveError("capture: %d channel(s) x %d samples need %d values; this drive's capture buffer holds %d "
                             "(HELLO capture_buf_words32): at most %d samples" %
                             (len(channels), samples, len(channels) * samples, depth, depth // len(channels)))
        qs = [QUANTITY[CHANNEL[c][0]] for c in channels] + [0] * (4 - len(channels))
        self.request(CMD["CAPTURE_SETUP"], struct.pack("<H4HHHHHHi", len(channels), *qs, samples, pre, decim,
                                                        TRIGGER[kind], tch, level))
        end = time.monotonic() + timeout_s
        while True:
            st, ns, nc, first, dec = struct.unpack_from("<HHHIH", self.request(CMD["CAPTURE_STATUS"]))
            if st == CAPTURE_STATE["DONE"]:
                break
            if st == CAPTURE_STATE["OFF"] or time.monotonic() > end:
                raise DriveError("capture: not triggered within %.0f s" % timeout_s)
            time.sleep(0.05)
        rows = []
        k = 0
        while k < ns:
            pl = self.request(CMD["CAPTURE_READ"], struct.pack("<HH", k, ns - k))
            _, n = struct.unpack_from("<HH", pl)
            if n == 0:
                raise DriveError("capture: read-out returned no samples")
            vals = struct.unpack_from("<%di" % (n * nc), pl, 4)
            for s in range(n):
                rows.append(vals[s * nc:(s + 1) * nc])
            k += n
        ticks = [(first + s * dec) & 0xFFFFFFFF for s in range(ns)]
        cols = {}
        for j, c in enumerate(channels):
            base = CHANNEL[c][1]
            cols[c] = [r[j] if base is None else self.si(r[j], base) for r in rows]
        return ticks, cols

    # ---- parameters -------------------------------------------------------------------------
    def params(self):
        """The parameter table: a list of rows {index, id, name, unit, fmt, frac, base, flags, min, max,
        default} (cached while HELLO's hash matches)."""
        if self._params is not None:
            return self._params
        h = self.hello()
        rows = []
        for i in range(h["param_count"]):
            pl = self.request(CMD["PARAM_DESC"], struct.pack("<H", i))
            idx, pid, frac, flags, lo, hi, dflt, base, nlen = struct.unpack_from("<HHHHiiiHH", pl)
            name = pl[24:24 + nlen].decode("ascii")
            unit = pl[24 + nlen:].decode("ascii")
            rows.append({"index": idx, "id": pid, "name": name, "unit": unit, "frac": frac, "base": base,
                         "flags": flags, "min": lo, "max": hi, "default": dflt})
        self._params = rows
        return rows

    def _row(self, name):
        for r in self.params():
            if r["name"] == name:
                return r
        raise DriveError("no parameter named %r (params list shows them)" % name)

    def _scale(self, r):
        """SI per raw count of a row: 2^-frac times its base (PARAM_DESC's base code)."""
        return self.bases()[PARAM_BASE.get(r["base"], "one")] / float(1 << r["frac"])

    def param_get(self, name):
        r = self._row(name)
        _, v = struct.unpack_from("<Hi", self.request(CMD["PARAM_READ"], struct.pack("<H", r["id"])))
        return v * self._scale(r)

    def param_set(self, name, value):
        r = self._row(name)
        # the wire carries an i32: a value beyond it is sent as the nearest i32, which the drive
        # refuses as out of range like any other
        raw = max(-(1 << 31), min((1 << 31) - 1, int(round(float(value) / self._scale(r)))))
        _, v = struct.unpack_from("<Hi", self.request(CMD["PARAM_WRITE"], struct.pack("<Hi", r["id"], raw)))
        return v * self._scale(r)

    def firmware_toml(self):
        """The [firmware] section dtc-sil and dtc_config_gen read (docs/sil.md: the machine and
        inverter values the firmware assumes), from the parameters in force: each key from the row
        whose field it is (FIRMWARE_KEYS), in SI. Returns (text, rows left out)."""
        lines = ["[firmware]"]
        done = set()
        for r in self.params():
            field = r["name"].rsplit(".", 1)[-1]
            if field not in FIRMWARE_KEYS:
                continue
            key, conv = FIRMWARE_KEYS[field]
            v = self.param_get(r["name"])
            if conv == "ts":
                v *= self.info["isr_period_ns"] * 1e-9
            lines.append("%s = %.9g  # %s" % (key, v, r["name"]))
            done.add(r["name"])
        left = [r["name"] for r in self.params() if r["name"] not in done]
        return "\n".join(lines) + "\n", left

    # ---- identification (app_ident.h, docs/commissioning.md) ---------------------------------
    def identify_start(self):
        self.request(CMD["IDENTIFY"], struct.pack("<H", IDENT_SUB["START"]))

    def identify_status(self):
        _, step, fail, fail_step, detail, state = struct.unpack_from(
            "<HHHHhH", self.request(CMD["IDENTIFY"], struct.pack("<H", IDENT_SUB["STATUS"])))
        return {"step": IDENT_STEP.get(step, str(step)), "fail": IDENT_FAIL.get(fail, "ok" if fail == 0 else str(fail)),
                "fail_step": IDENT_STEP.get(fail_step, str(fail_step)), "fail_detail": detail,
                "state": STATE.get(state, str(state))}

    def identify_result(self):
        """The results so far in SI (the bases of HELLO, the control period, the board's device
        data from the parameters): the quantities `dtc-sil identify` reports under the same keys."""
        pl = self.request(CMD["IDENTIFY"], struct.pack("<H", IDENT_SUB["RESULT"]))
        (_, step, axis, r, v0, l_ts, p, rev, off, cpt, t_rs, t_ls, t_enc) = struct.unpack_from("<HHHiiiHHHiIII", pl)
        lev = struct.unpack_from("<8i", pl, 40)
        psi_pu, j_q12, b_pu, tc_pu, t_spin = struct.unpack_from("<iiiiI", pl, 72)
        b = self.bases()
        ts = self.info["isr_period_ns"] * 1e-9
        z_b = b["z"]
        r_on = self.param_get("board.r_on_iq")
        v_ce = self.param_get("board.v_ce_iq")
        v_d = self.param_get("board.v_d_iq")
        r_slope = r / IQ_ONE * z_b
        v0_v = v0 / IQ_ONE * b["v"]
        # V0 = g (V_CE + V_d + 2 V_dc T_d / T_s) on the injection axis, g = 1/sqrt(3) on the beta
        # axis (FSTP), 2/3 on the alpha axis (SSTP) (docs/commissioning.md)
        g = 2.0 / 3.0 if axis == 0 else 1.0 / math.sqrt(3.0)
        off_e = off / 65536.0 * 2.0 * math.pi
        q = {
            "step": IDENT_STEP.get(step, str(step)),
            "injection_axis": "alpha" if axis == 0 else "beta",
            "r_slope_ohm": r_slope, "rs_ohm": r_slope - r_on, "v0_v": v0_v,
            "drop_at_rated_v": v0_v + r_on * b["i"],
            "dead_time_s": max(0.0, (v0_v / g - v_ce - v_d) * ts / (2.0 * b["v"])),
            "ls_h": l_ts / IQ_ONE * z_b * ts, "pole_pairs": p, "encoder_reversed": bool(rev),
            "encoder_offset_el_deg": off_e * 180.0 / math.pi,
            "encoder_offset_rad": math.remainder(-off_e / p, 2.0 * math.pi) if p > 0 else 0.0,
            "counts_per_turn": cpt,
            "duration_s": {"rs": t_rs * ts, "ls": t_ls * ts, "encoder": t_enc * ts, "spin": t_spin * ts},
            "rs_fit_points": [{"i_a": lev[k] / IQ_ONE * b["i"], "v_v": lev[4 + k] / IQ_ONE * b["v"]} for k in range(4)],
        }
        # the spin step (app_ident.h formats): psi_m in pu of V_b / w_b; J, B, T_c over k_t I_b
        # (k_t = 1.5 p psi_m), per encoder count (2 pi / enc_counts mechanical rad) and period
        psi = psi_pu / IQ_ONE * b["v"] / b["w"]
        kt_ib = 1.5 * p * psi * b["i"]
        rad_per_count = 2.0 * math.pi / self.param_get("board.enc_counts")
        machine = struct.unpack_from("<H", pl, 92)[0] if len(pl) >= 114 else 0
        q["machine"] = "im" if machine == 1 else "pm"
        if machine == 1:
            # an induction machine (app_ident_im.h, docs/commissioning.md "Induction machine"), as
            # dtc-sil identify reports it: L_s, sigma L_s, tau_r, R_r (L_lr = L_ls, so L_r = L_s); the
            # spin's psi is L_s i_d (L_s at the configured flux) and k_t = 1.5 p L_M i_d with
            # L_M = L_s - sigma L_s; the leakage split l = L_s (1 - sqrt(1 - sigma)), L_m = L_s - l
            ls_ts, lsig_ts, taur_q4, rr_pu, id_pu = struct.unpack_from("<iiiii", pl, 94)
            ls = ls_ts / IQ_ONE * z_b * ts
            lsig = lsig_ts / IQ_ONE * z_b * ts
            id_a = id_pu / IQ_ONE * b["i"]
            ls_spin = psi / id_a if id_a > 0.0 else 0.0
            ls_m = ls_spin if ls_spin > lsig else ls
            l_leak = ls_m * (1.0 - math.sqrt(max(0.0, 1.0 - lsig / ls_m))) if ls_m > 0.0 else 0.0
            kt_ib = 1.5 * p * (ls_spin - lsig) * id_a * b["i"] if ls_spin > lsig else 0.0
            del q["encoder_offset_el_deg"], q["encoder_offset_rad"]
            del q["ls_h"]
            q.update({"ls_h": ls, "sigma_ls_h": lsig, "tau_r_s": taur_q4 / 16.0 * ts, "rr_ohm": rr_pu / IQ_ONE * z_b,
                      "ls_spin_h": ls_spin, "id_a": id_a, "lm_h": ls_m - l_leak, "lls_h": l_leak, "llr_h": l_leak,
                      "j_kgm2": j_q12 / 4096.0 * kt_ib * ts * ts / rad_per_count,
                      "b_nm_s_per_rad": b_pu / IQ_ONE * kt_ib * ts / rad_per_count, "coulomb_nm": tc_pu / IQ_ONE * kt_ib})
            return q
        if len(pl) >= 118:
            # step ls's quadrature axis (app_ident.h res.lq_q12, res.salient): L_q = L_d lq_q12 / 2^12
            lq_q12, salient = struct.unpack_from("<HH", pl, 114)
            q.update({"ld_h": q["ls_h"], "lq_h": q["ls_h"] * lq_q12 / 4096.0,
                      "saliency_ratio": lq_q12 / 4096.0, "salient": bool(salient)})
        q.update({"psi_m_wb": psi, "j_kgm2": j_q12 / 4096.0 * kt_ib * ts * ts / rad_per_count,
                  "b_nm_s_per_rad": b_pu / IQ_ONE * kt_ib * ts / rad_per_count, "coulomb_nm": tc_pu / IQ_ONE * kt_ib})
        return q

    def identify(self, timeout_s=30.0, poll_s=0.1):
        """Starts the identification, waits for its end, disarms (READY again) and returns
        (status, result): DriveError when it is refused, fails or does not end in timeout_s. A drive
        still calibrating its current sensors (just powered, or just connected to) is waited for
        first, within the same timeout: it would refuse the start with NOT_CALIBRATED."""
        end = time.monotonic() + timeout_s
        while self.status()["state"] in ("init", "calibrate") and time.monotonic() < end:
            time.sleep(poll_s)
        self.identify_start()
        try:
            while True:
                st = self.identify_status()
                if st["state"] == "ident" and st["step"] in ("done", "failed"):
                    break
                if st["state"] in ("fault", "ready") and st["step"] != "idle":
                    break
                if time.monotonic() > end:
                    raise DriveError("the identification did not end within %.0f s (step %s)" % (timeout_s, st["step"]))
                time.sleep(poll_s)
            res = self.identify_result()
        finally:
            self.disarm()
        if st["step"] != "done":
            why = st["fail"]
            if st["fail"] == "bounds":
                why += " (%s)" % IDENT_QUANTITY.get(st["fail_detail"], st["fail_detail"])
            elif st["fail_detail"]:
                why += " (detail %d)" % st["fail_detail"]
            if st["state"] == "fault":
                why = "the drive tripped (%s)" % self.status()["fault"]
            raise DriveError("the identification failed in step %s: %s" % (st["fail_step"] if st["step"] == "failed"
                                                                           else st["step"], why), detail=(st, res))
        return st, res

    def identify_apply(self):
        """IDENT_APPLY (proto.h): the finished identification's results into the parameters in force
        (app_ident_apply). Returns [(name, before, after)] in SI for the rows it may write on the
        drive's law (identify_apply_rows) whose value changed; a refusal names its reason
        (app_ident_apply_err, or the law check's dtc_err code)."""
        rows = self.identify_apply_rows()
        before = {n: self.param_get(n) for n in rows}
        try:
            (n,) = struct.unpack_from("<H", self.request(CMD["IDENT_APPLY"]))
        except DriveError as e:
            if e.code in (ERR["STATE"], ERR["RANGE"]) and e.detail is not None:
                why = APPLY_ERR.get(e.detail) if e.detail > 0 else "law check refused the result (dtc_err %d)" % e.detail
                raise DriveError("%s: %s" % (e, why), e.code, e.detail) from None
            raise
        after = {k: self.param_get(k) for k in rows}
        changed = [(k, before[k], after[k]) for k in rows if after[k] != before[k]]
        return n, changed

    def identify_apply_rows(self):
        """The rows IDENT_APPLY may write on the drive's law (HELLO's law)."""
        law = self.hello()["law"]
        if law == LAW["PM_DTC"]:
            return IDENT_APPLY_ROWS
        if law == LAW["IM_DFOC"]:
            return IDENT_APPLY_ROWS_DFOC
        if law == LAW["IM_DSVM"]:
            return IDENT_APPLY_ROWS_DSVM
        return IDENT_APPLY_ROWS_IM if LAW["IM_DTC"] <= law <= LAW["IM_DSVM"] else _IDENT_APPLY_COMMON

    def save(self):
        (seq,) = struct.unpack_from("<I", self.request(CMD["PARAMS_SAVE"]))
        return seq

    def restore(self, source=0):
        self.request(CMD["PARAMS_RESTORE"], struct.pack("<H", source))
        self._params = None


# [firmware] keys (dtc-sil keys) of the configuration's fields: field name -> (key, conversion);
# "si": the row's SI value as it is, "ts": a ratio to the control period, times that period.
FIRMWARE_KEYS = {
    "rs_iq": ("rs_ohm", "si"), "ls_iq": ("ls_h", "si"), "lq_iq": ("lq_h", "si"), "psi_m_iq": ("psi_m_wb", "si"),
    "rr_iq": ("rr_ohm", "si"), "lls_iq": ("lls_h", "si"), "llr_iq": ("llr_h", "si"), "lm_iq": ("lm_h", "si"),
    "v_ce_iq": ("v_ce_v", "si"), "v_d_iq": ("v_d_v", "si"), "r_on_iq": ("r_on_ohm", "si"),
    "td_ts_q15": ("dead_time_s", "ts"),
}

# PARAM_DESC's base codes (proto.h enum proto_base) -> Drive.bases() keys; "one": dimensionless.
PARAM_BASE = {v: k.lower() for k, v in _enum(_PROTO, "PROTO_BASE_").items()}

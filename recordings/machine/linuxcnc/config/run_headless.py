#!/usr/bin/python3
"""run_headless.py: the "display" of fiveaxis-xyzac.ini, a headless driver for LinuxCNC 2.9
(recordings/machine/linuxcnc/make-traces). The linuxcnc script runs it in the foreground as
`run_headless.py -ini INIFILE`; LinuxCNC shuts down when it exits. It uses only the `linuxcnc`
python module (NML status/command/error channels) and halcmd/halsampler.

Environment (set by make-traces):
  FIVEAXIS_MODE=run     estop reset, machine on, home, auto mode, open FIVEAXIS_NGC, start
                        halsampler -t into FIVEAXIS_RAW, enable sampler.0, cycle start, wait until
                        the interpreter is idle again, +300 ms, disable the sampler, drain the FIFO.
  FIVEAXIS_MODE=verify  MDI: M428 (TCP), G1 to world poses, compare joint positions with the Hermle
                        model P_M = Rot_x(A) Rot_z(C) P_W; JSON to FIVEAXIS_OUT.
  FIVEAXIS_LOG          messages from LinuxCNC's error channel and the driver's own notes.
Exit status 0 on success.
"""
import json
import math
import os
import subprocess
import sys
import time

import linuxcnc

LOG = open(os.environ.get("FIVEAXIS_LOG", "/dev/stderr"), "a", buffering=1)


def log(msg):
    LOG.write(f"[run_headless {time.strftime('%H:%M:%S')}] {msg}\n")


s = linuxcnc.stat()
c = linuxcnc.command()
e = linuxcnc.error_channel()
errors = []


def drain_errors():
    while True:
        m = e.poll()
        if not m:
            return
        kind, text = m
        kinds = {linuxcnc.NML_ERROR: "NML_ERROR", linuxcnc.OPERATOR_ERROR: "OPERATOR_ERROR",
                 linuxcnc.NML_TEXT: "NML_TEXT", linuxcnc.OPERATOR_TEXT: "OPERATOR_TEXT",
                 linuxcnc.NML_DISPLAY: "NML_DISPLAY", linuxcnc.OPERATOR_DISPLAY: "OPERATOR_DISPLAY"}
        k = kinds.get(kind, str(kind))
        log(f"linuxcnc {k}: {text}")
        if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
            errors.append(text)


def wait_for(cond, timeout, what):
    t0 = time.time()
    while time.time() - t0 < timeout:
        s.poll()
        drain_errors()
        if cond():
            return
        time.sleep(0.01)
    raise SystemExit(f"timeout ({timeout} s) waiting for {what}")


def halcmd(*args):
    return subprocess.run(["halcmd", *args], check=True, capture_output=True, text=True).stdout.strip()


def machine_up():
    # the task may need a moment after the display starts
    wait_for(lambda: True, 1, "status")
    c.state(linuxcnc.STATE_ESTOP_RESET)
    c.wait_complete()
    c.state(linuxcnc.STATE_ON)
    c.wait_complete()
    wait_for(lambda: s.task_state == linuxcnc.STATE_ON, 10, "machine on")
    c.mode(linuxcnc.MODE_MANUAL)
    c.wait_complete()
    c.teleop_enable(0)
    c.wait_complete()
    c.home(-1)
    c.wait_complete()
    wait_for(lambda: all(s.homed[j] for j in range(s.joints)), 20, "all joints homed")
    log(f"machine on and homed; kinematics_type={s.kinematics_type} joints={s.joints}")


def mdi(cmd, timeout=60):
    c.mode(linuxcnc.MODE_MDI)
    c.wait_complete()
    c.mdi(cmd)
    c.wait_complete(timeout)
    wait_for(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.inpos and s.queue == 0, timeout, f"MDI '{cmd}'")


def hermle_joints(x, y, z, a_deg, c_deg):
    """P_M = Rot_x(A) Rot_z(C) P_W, right-handed, the project's hermle-c600u model."""
    a, cc = math.radians(a_deg), math.radians(c_deg)
    u = math.cos(cc) * x - math.sin(cc) * y
    v = math.sin(cc) * x + math.cos(cc) * y
    return (u, math.cos(a) * v - math.sin(a) * z, math.sin(a) * v + math.cos(a) * z)


def verify(out):
    machine_up()
    mdi("G21 G90 G94 G17 G64 G49 G92.1")
    mdi("G10 L2 P1 X0 Y0 Z0 A0 C0")
    mdi("G54")
    mdi("M428")
    halcmd_type = float(halcmd("getp", "motion.switchkins-type"))
    poses = [(10.0, 20.0, 30.0, 30.0, 40.0), (25.0, 0.0, -8.0, 1.0, 180.0), (-15.0, 35.0, 5.0, -20.0, 250.0),
             (40.0, -30.0, 60.0, 75.0, -120.0), (0.0, 50.0, 0.0, 90.0, 0.0), (50.0, 0.0, 0.0, 0.0, 90.0)]
    rows = []
    worst = 0.0
    for (x, y, z, a, cdeg) in poses:
        mdi(f"G1 X{x} Y{y} Z{z} A{a} C{cdeg} F5000", timeout=120)
        time.sleep(0.05)
        s.poll()
        jp = list(s.joint_actual_position[:5])
        world = list(s.actual_position[:6])
        hx, hy, hz = hermle_joints(x, y, z, a, cdeg)
        # alternatives, to name a convention difference should there be one
        alt = {
            "hermle": (hx, hy, hz, a, cdeg),
            "A negated": hermle_joints(x, y, z, -a, cdeg) + (a, cdeg),
            "C negated": hermle_joints(x, y, z, a, -cdeg) + (a, cdeg),
            "A and C negated": hermle_joints(x, y, z, -a, -cdeg) + (a, cdeg),
        }
        errs = {k: max(abs(p - q) for p, q in zip(jp, v)) for k, v in alt.items()}
        worst = max(worst, errs["hermle"])
        rows.append({"world_xyzac": [x, y, z, a, cdeg], "linuxcnc_world_fb": [round(w, 6) for w in world[:3]] + [round(world[3], 6), round(world[5], 6)],
                     "linuxcnc_joints": [round(v, 6) for v in jp], "hermle_joints": [round(v, 6) for v in (hx, hy, hz, a, cdeg)],
                     "max_abs_diff": {k: round(v, 6) for k, v in errs.items()}})
        log(f"pose {x,y,z,a,cdeg}: linuxcnc joints {[round(v, 4) for v in jp]} hermle {[round(v, 4) for v in (hx, hy, hz, a, cdeg)]} diff {errs['hermle']:.2e}")
    mdi("G1 A0 C0 F5000")
    mdi("G1 X0 Y0 Z0 F5000")
    mdi("M429")
    res = {"switchkins_type_after_M428": halcmd_type, "poses": rows, "max_abs_diff_hermle": worst,
           "same_as_hermle": worst < 1e-6, "errors": errors}
    with open(out, "w") as f:
        json.dump(res, f, indent=1)
    return 0 if worst < 1e-6 and not errors else 1


def run(ngc, raw):
    machine_up()
    # the trajectory planner settings in effect (none are set in the ini: LinuxCNC's defaults)
    tp = [l.split() for l in halcmd("show", "pin", "ini.traj_arc_blend").splitlines() if "ini.traj_arc_blend" in l]
    log("TP settings: " + " ".join(f"{f[-1].replace('ini.traj_', '')}={f[-2]}" for f in tp))
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(ngc)
    c.wait_complete()
    wait_for(lambda: s.file == ngc, 10, "program open")
    sampler = subprocess.Popen(["halsampler", "-t", "-c", "0"], stdout=open(raw, "w"), stderr=subprocess.PIPE, text=True)
    time.sleep(0.3)  # halsampler attached to the FIFO
    halcmd("setp", "sampler.0.enable", "1")
    c.auto(linuxcnc.AUTO_RUN, 0)  # cycle start
    t0 = time.time()
    log(f"cycle start: {ngc}")
    wait_for(lambda: s.interp_state != linuxcnc.INTERP_IDLE, 10, "program started")
    wait_for(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and s.inpos, 600, "program end")
    log(f"program ended after {time.time() - t0:.2f} s wall clock; task_state={s.task_state} errors={len(errors)}")
    time.sleep(0.3)
    halcmd("setp", "sampler.0.enable", "0")
    overruns = halcmd("getp", "sampler.0.overruns")
    # let halsampler empty the FIFO
    for _ in range(500):
        if int(halcmd("getp", "sampler.0.curr-depth")) == 0:
            break
        time.sleep(0.02)
    time.sleep(0.2)
    sampler.terminate()
    _, err = sampler.communicate(timeout=10)
    with open(raw) as f:
        rows = sum(1 for _ in f)
    log(f"sampler: {rows} rows, overruns={overruns}, halsampler stderr={err.strip()!r}")
    with open(raw + ".meta.json", "w") as f:
        json.dump({"rows": rows, "overruns": int(overruns), "errors": errors,
                   "wall_clock_s": time.time() - t0}, f, indent=1)
    return 0 if not errors and int(overruns) == 0 else 1


def main():
    mode = os.environ.get("FIVEAXIS_MODE", "run")
    try:
        if mode == "verify":
            rc = verify(os.environ["FIVEAXIS_OUT"])
        else:
            rc = run(os.path.abspath(os.environ["FIVEAXIS_NGC"]), os.path.abspath(os.environ["FIVEAXIS_RAW"]))
    except SystemExit as ex:
        log(f"FAILED: {ex}")
        rc = 2
    except Exception as ex:  # noqa: BLE001 - report anything, LinuxCNC must still shut down
        log(f"FAILED: {type(ex).__name__}: {ex}")
        rc = 2
    drain_errors()
    with open(os.environ.get("FIVEAXIS_STATUS", "/dev/null"), "w") as f:
        f.write(f"{rc}\n")
    return rc


if __name__ == "__main__":
    sys.exit(main())

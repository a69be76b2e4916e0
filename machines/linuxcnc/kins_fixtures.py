#!/usr/bin/python3
"""Forward kinematics of LinuxCNC's own five-axis kinematics modules, as fixtures for tests/chains.rs.

Loads each installed module (Debian linuxcnc-uspace 2.9: /usr/lib/linuxcnc/modules/*.so) in this process
with ctypes, sets its HAL pins to the sample configs' values (the machine files in ../ cite them), and calls
its kinematicsForward on random joint values within the machines' ranges. Writes kins_fixtures.csv:
machine, tool length T (mm), the five joints in the machine file's order (mm, deg) and the world point the
control computes (mm). The tests compare our forward kinematics with the world point minus (0, 0, T): the
program point, since LinuxCNC's canon adds T to Z (see the machine files).

Run with the system python (Debian's, which finds LinuxCNC's HAL library): /usr/bin/python3 kins_fixtures.py
It needs no running LinuxCNC: liblinuxcnchal exports what the modules call; halcmd sets their pins.
"""
import ctypes
import csv
import os
import random
import subprocess
import sys

MODULES = "/usr/lib/linuxcnc/modules"
HERE = os.path.dirname(os.path.abspath(__file__))


class EmcPose(ctypes.Structure):
    _fields_ = [(n, ctypes.c_double) for n in "x y z a b c u v w".split()]


# machine file, module, kinematics type to switch to (None: the start-up one), pins per tool length T,
# LinuxCNC joint index of each of our five axes (file order), extra joints held at 0, ranges to draw from.
MACHINES = [
    ("linuxcnc-xyzbc-trt", "xyzbc-trt-kins", None,
     lambda t: {"x-rot-point": 0, "y-rot-point": 0, "z-rot-point": 0, "x-offset": -20, "z-offset": -15, "tool-offset": t},
     [0, 1, 2, 3, 4], [(-200, 200), (-100, 100), (-120, 120), (-100, 50), (-720, 720)], [0, 10]),
    ("linuxcnc-xyzac-trt", "xyzac-trt-kins", None,
     lambda t: {"x-rot-point": 0, "y-rot-point": 0, "z-rot-point": 0, "y-offset": 20, "z-offset": 10, "tool-offset": t},
     [0, 1, 2, 3, 4], [(-200, 200), (-100, 100), (-120, 120), (-100, 50), (-720, 720)], [0, 10]),
    ("linuxcnc-xyzab-tdr", "xyzab_tdr_kins", 1,
     lambda t: {"x-rot-point": -50, "y-rot-point": -50, "z-rot-point": -100, "x-offset": -20, "z-offset": -10, "tool-offset-z": t},
     # our file order is X Y Z B A; LinuxCNC's joints are X Y Z A B
     [0, 1, 2, 4, 3], [(-200, 200), (-200, 200), (-300, 300), (-180, 180), (-720, 720)], [0, 30]),
    ("linuxcnc-max5", "maxkins", None,
     lambda t: {"pivot-length": 0},
     # our file order is X Y Z C B; LinuxCNC's joints are X Y Z A(dummy) B C
     [0, 1, 2, 5, 4], [(-100, 200), (-60, 60), (-149, 1), (-720, 720), (-90, 90)], [0]),
    ("linuxcnc-bridgemill", "5axiskins", None,
     lambda t: {"pivot-length": 250 + t},
     # X Y Z C B ours; LinuxCNC's X Y Z B C W
     [0, 1, 2, 4, 3], [(-500, 500), (-500, 500), (-500, 100), (-720, 720), (-120, 120)], [0, 100]),
]


def halcmd(*args):
    subprocess.run(["halcmd", *args], check=True, capture_output=True)


def forward_rows(name, rng_seed):
    """Rows of one machine: its module loaded alone in this process (the modules export the same symbols)."""
    _, module, switch, pins, order, ranges, tools = next(m for m in MACHINES if m[0] == name)
    ctypes.CDLL("/usr/lib/liblinuxcnchal.so.0", mode=ctypes.RTLD_GLOBAL)
    m = ctypes.CDLL(f"{MODULES}/{module}.so", mode=ctypes.RTLD_GLOBAL)
    assert m.rtapi_app_main() == 0, module
    rng = random.Random(rng_seed)
    rows = []
    try:
        m.kinematicsType()
        if switch is not None:
            assert m.kinematicsSwitch(switch) == 0, module
        for t in tools:
            for pin, value in pins(t).items():
                halcmd("setp", f"{module}.{pin}", str(value))
            for _ in range(40):
                ours = [rng.uniform(lo, hi) for lo, hi in ranges]
                joints = (ctypes.c_double * 16)()
                for k, j in enumerate(order):
                    joints[j] = ours[k]
                pose = EmcPose()
                f1, f2 = ctypes.c_ulong(0), ctypes.c_ulong(0)
                assert m.kinematicsForward(joints, ctypes.byref(pose), ctypes.byref(f1), ctypes.byref(f2)) == 0
                rows.append([name, t, *[f"{v:.12f}" for v in ours], f"{pose.x:.12f}", f"{pose.y:.12f}", f"{pose.z:.12f}"])
    finally:
        m.rtapi_app_exit()
    return rows


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--one":
        csv.writer(sys.stdout).writerows(forward_rows(sys.argv[2], sys.argv[2]))
        return
    rows = []
    for name, *_ in MACHINES:
        out = subprocess.run([sys.executable, __file__, "--one", name], check=True, capture_output=True, text=True).stdout
        rows.extend(r for r in csv.reader(out.splitlines()) if r and r[0] == name)
    with open(os.path.join(HERE, "kins_fixtures.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["machine", "tool_mm", "q0", "q1", "q2", "q3", "q4", "x_mm", "y_mm", "z_mm"])
        w.writerows(rows)
    print(f"{len(rows)} rows")


if __name__ == "__main__":
    main()

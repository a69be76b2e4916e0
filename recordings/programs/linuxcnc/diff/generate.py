#!/usr/bin/env python3
"""Generated programs for the differential test against LinuxCNC's own interpreter (a development aid,
run by hand; tests/readers/linuxcnc/differential.rs reads what this writes).

    RS274=/path/to/rs274 python3 generate.py OUT_DIR SEED COUNT

writes OUT_DIR/NNNN.ngc, runs rs274 (Debian 12's linuxcnc-uspace 2.9; see ../parameters/make_canon.sh
for running it unpacked) on each with OUT_DIR/tools.tbl, and keeps its canonical moves and the states
that place them (NNNN.canon) or, where it refuses the program, its message (NNNN.err). Then:

    FIVEAXIS_DIFF_DIR=OUT_DIR cargo test -p fiveaxis-tests --test integration differential -- --ignored --nocapture

They are read on linuxcnc-xyzac-trt (its machine zero and stored points are rs274's: 0), so rotary
words are A and C. The programs mix what moves the tool: straight and arc moves (R and centre forms, G90.1/G91.1, the three
planes, P turns), rotary axes, G90/G91, G20/G21, coordinate systems with rotation (G10 L2/L20 R), G92 and
its cancels, G52, G53, G28/G30 with their stored points, feeds in G93/G94/G95, and cutter radius
compensation (G41.1/G42.1), tool changes and G43/G49 (of a tool 0 long), canned cycles in each plane (G73, G81-G83, G85, G86, G89 with
G98/G99, P, Q, L), polar coordinates, and O-word flow (repeat, while, sub and call, if) and
M70/M72 around some of them. Nothing here is a reference: rs274's output is.

    RS274=/path/to/rs274 python3 generate.py --fixture OUT_DIR SEED COUNT

makes the committed fixture (OUT_DIR/programs.ngcs and OUT_DIR/rs274.txt) that
`readers::linuxcnc::differential::generated_programs_read_as_rs274_runs_them` reads in every test run:
programs without the constructs read differently by design (M70/M72, whose F and S the 2.9 releases
write back where this rs274 does not; a G93 under cutter compensation, refused).
"""
import os, random, subprocess, sys

KEEP = ("STRAIGHT_", "ARC_FEED", "USE_LENGTH_UNITS", "SELECT_PLANE", "SET_G5X_OFFSET", "SET_G92_OFFSET",
        "SET_XY_ROTATION", "SET_FEED_RATE", "SET_FEED_MODE", "SET_SPINDLE_SPEED")


def num(r, lo, hi, places=3):
    return f"{r.uniform(lo, hi):.{places}f}".rstrip("0").rstrip(".") or "0"


class Gen:
    def __init__(self, r, fixture=False):
        self.r = r
        # For the committed fixture: none of the constructs whose reading differs from this rs274 by
        # design (M72's F and S as 2.9's releases write them back; G93 under compensation refused).
        self.fixture = fixture
        self.lines = []
        self.inch = r.random() < 0.25
        self.rel = False
        self.plane = 17
        self.feedmode = 94
        self.comp = False

    def unit(self):
        return 1 / 25.4 if self.inch else 1.0

    def v(self, lo=-40, hi=40):
        u = self.unit()
        return num(self.r, lo * u, hi * u, 4 if self.inch else 3)

    def axes(self, letters="XYZ", least=1):
        r = self.r
        picked = [l for l in letters if r.random() < 0.6] or list(r.sample(letters, least))
        return " ".join(f"{l}{self.v() if l in 'XYZ' else num(r, -90, 90, 2)}" for l in picked)

    def feed(self):
        r = self.r
        if self.feedmode == 93:
            return f" F{num(r, 0.5, 20, 2)}"
        if self.feedmode == 95:
            return f" F{num(r, 0.01, 0.3, 3)}" if r.random() < 0.5 else ""
        return f" F{num(r, 50, 2000, 1)}" if r.random() < 0.3 else ""

    def arc(self):
        r = self.r
        g = r.choice(["G2", "G3"])
        a, b, c = {17: "XYZ", 18: "ZXY", 19: "YZX"}[self.plane]
        ij = {17: "IJ", 18: "KI", 19: "JK"}[self.plane]
        if r.random() < 0.5:
            # R form: an end within the diameter's reach.
            rad = r.uniform(5, 30)
            return f"{g} {a}{self.v(-20, 20)} {b}{self.v(-20, 20)} R{num(r, rad * self.unit(), rad * self.unit(), 4)}" + (f" {c}{self.v()}" if r.random() < 0.3 else "")
        # Centre form: the end on the circle about the centre from wherever the tool is is not known
        # here (G91, offsets); a full circle (no end) or a centre offset with an end the same distance.
        off = [float(self.v(-15, 15)), float(self.v(-15, 15))]
        words = f"{g} {ij[0]}{off[0]:g} {ij[1]}{off[1]:g}"
        if r.random() < 0.3:
            words += f" P{r.randint(1, 3)}"
        if r.random() < 0.3:
            words += f" {c}{self.v()}"
        return words

    def statement(self, k=None):
        r = self.r
        k = r.random() if k is None else k
        L = self.lines
        if k < 0.22:
            L.append(f"G0 {self.axes('XYZAC' if r.random() < 0.3 else 'XYZ')}")
        elif k < 0.42:
            L.append(f"G1 {self.axes('XYZAC' if r.random() < 0.3 else 'XYZ')}{self.feed()}")
        elif k < 0.55 and (not self.comp or self.plane == 17):
            L.append(self.arc() + self.feed())
        elif k < 0.60:
            p = r.randint(1, 9)
            rot = f" R{num(r, -90, 90, 2)}" if r.random() < 0.5 else ""
            L.append(f"G10 L{r.choice([2, 20])} P{p} {self.axes('XYZ')}{rot}")
        elif k < 0.64 and not self.comp:
            L.append(r.choice(["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"]))
        elif k < 0.68 and not self.comp:
            L.append(r.choice([f"G92 {self.axes('XYZ')}", "G92.1", "G92.2", "G92.3", f"G52 {self.axes('XYZ')}"]))
        elif k < 0.72:
            self.rel = not self.rel
            L.append("G91" if self.rel else "G90")
        elif k < 0.74 and not self.comp:
            self.inch = not self.inch
            L.append("G20" if self.inch else "G21")
        elif k < 0.77 and not self.comp:
            self.plane = r.choice([17, 18, 19])
            L.append(f"G{self.plane}")
        elif k < 0.80:
            L.append(r.choice(["G90.1", "G91.1"]))
        elif k < 0.84 and not (self.fixture and self.comp):
            self.feedmode = r.choice([93, 94, 95])
            L.append(f"G{self.feedmode}" + (f" F{num(r, 100, 1500, 1)}" if self.feedmode == 94 else (" F0.1" if self.feedmode == 95 else "")))
        elif k < 0.86 and not self.comp:
            L.append(f"G53 G{r.choice([0, 1])} {self.axes('XYZ')}" + (self.feed() if self.feedmode == 93 else ""))
        elif k < 0.89 and not self.comp:
            L.append(r.choice(["G28", "G30", "G28.1", "G30.1", f"G28 {self.axes('XYZ')}", f"G30 {self.axes('XYZ')}"]))
        elif k < 0.93 and self.plane == 17 and self.feedmode != 93:
            if self.comp:
                L.append(f"G40 G1 {self.axes('XY', 2)}")
            else:
                L.append(f"{r.choice(['G41.1', 'G42.1'])} D{num(r, 1, 6, 2)}")
                L.append(f"G1 {self.axes('XY', 2)}")
            self.comp = not self.comp
        elif k < 0.96 and not self.comp and self.feedmode != 93:
            # A canned cycle (its plane's), holes after it, then G80 or not.
            g = r.choice(["G81", "G82", "G83", "G73", "G85", "G86", "G89"])
            a, b, c = {17: "XYZ", 18: "ZXY", 19: "YZX"}[self.plane]
            words = f"{r.choice(['G98', 'G99'])} {g} {a}{self.v()} {b}{self.v()} {c}{self.v(-20, 0)} R{self.v(0, 10)}"
            if g in ("G83", "G73"):
                words += f" Q{self.v(0.5, 8)}"
            if g in ("G82", "G86", "G89") or r.random() < 0.2:
                words += f" P{num(r, 0, 1, 2)}"
            if r.random() < 0.2:
                words += f" L{r.randint(1, 3)}"
            L.append(words)
            for _ in range(r.randint(0, 2)):
                L.append(self.axes(a + b + c))
            if r.random() < 0.7:
                L.append("G80")
        elif k < 0.965 and not self.comp:
            # Tool changes and a tool length of 0 (T1): the reader takes a tool's length from the
            # machine file, where LinuxCNC's current point drops by the table's at G43 (so T2's
            # 5 in would differ by design), and refuses G43.1.
            L.append(r.choice(["T1 M6 G43\nM3", "G43 H1", "G49", "T2 M6 G43 H1\nM3"]))
        elif k < 0.98 and self.plane == 17:
            # Polar coordinates: a radius and an angle (deg) in the XY plane.
            L.append(f"G{r.choice([0, 1])} @{self.v(0, 30)} ^{num(r, -180, 180, 2)}{self.feed()}")
        else:
            L.append(f"S{r.randint(500, 3000)} M3")

    def inner(self):
        """A statement that a loop or a subroutine may repeat: moves, arcs, G90/G91, offsets, polar."""
        r = self.r
        self.statement(r.choice([0.1, 0.3, 0.5, 0.57, 0.66, 0.70, 0.97]) if not self.comp else r.choice([0.1, 0.3]))

    def structure(self):
        """O-word flow around a few statements (a repeat, a while on a parameter, a subroutine called
        with an argument, an if) or M70/M72 around them: LinuxCNC's own, run as rs274 runs them."""
        r = self.r
        L = self.lines
        label = f"o{r.randint(100, 999)}"
        kind = r.choice(["repeat", "while", "sub", "if"] + ([] if self.fixture else ["m70"]))
        if kind == "repeat":
            L.append(f"{label} repeat [{r.randint(0, 3)}]")
            for _ in range(r.randint(1, 3)):
                self.inner()
            L.append(f"{label} endrepeat")
        elif kind == "while":
            L.append("#<n> = 0")
            L.append(f"{label} while [#<n> LT {r.randint(1, 3)}]")
            L.append(f"G1 X[#<n> * {self.v(1, 5)} + {self.v()}] Y[{self.v()} - #<n>]")
            self.inner()
            L.append("#<n> = [#<n> + 1]")
            L.append(f"{label} endwhile")
        elif kind == "sub":
            # Defined before its calls: LinuxCNC skips the definition in normal flow.
            L.append(f"{label} sub")
            L.append(f"G1 X[#1 + {self.v()}] Y[#1 * 0.5]")
            self.inner()
            L.append(f"{label} endsub")
            for _ in range(r.randint(1, 2)):
                L.append(f"{label} call [{self.v()}]")
        elif kind == "if":
            L.append(f"#<c> = {r.randint(0, 2)}")
            L.append(f"{label} if [#<c> EQ 1]")
            self.inner()
            L.append(f"{label} elseif [#<c> GT 1]")
            self.inner()
            L.append(f"{label} else")
            self.inner()
            L.append(f"{label} endif")
        else:
            L.append("M70")
            for _ in range(r.randint(1, 3)):
                self.inner()
            L.append("M72")

    def program(self, n):
        r = self.r
        head = ["G20" if self.inch else "G21", "G17 G90 G94 G40 G49 G54 G92.1", f"F{num(r, 100, 1000, 1)} S1000 M3"]
        # Stored points for G28 and G30 (#5161-5166, #5181-5186), where G28.1 and G30.1 store them.
        head.append(f"G0 X{self.v()} Y{self.v()} Z{self.v()}")
        head.append("G28.1")
        head.append(f"G0 X{self.v()} Y{self.v()} Z{self.v()}")
        head.append("G30.1")
        self.lines = head
        for _ in range(n):
            if not self.comp and self.r.random() < 0.12:
                self.structure()
            else:
                self.statement()
        if self.comp:
            self.lines.append(f"G40 G1 {self.axes('XY', 2)}")
        self.lines.append("M2")
        return "\n".join(self.lines) + "\n"


def main():
    if sys.argv[1] == "--fixture":
        return fixture(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    out, seed, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    rs274 = os.environ.get("RS274", "rs274")
    os.makedirs(out, exist_ok=True)
    table = os.path.join(out, "tools.tbl")
    with open(table, "w") as f:
        f.write("T1 P1 Z0 D10 ;\nT2 P2 Z5 D6 ;\n")
    r = random.Random(seed)
    refused = 0
    fixture_mode = os.environ.get("FIXTURE") == "1"
    for i in range(count):
        text = Gen(r, fixture_mode).program(r.randint(3, 10))
        base = os.path.join(out, f"{seed:04d}-{i:04d}")
        with open(base + ".ngc", "w") as f:
            f.write(text)
        run = subprocess.run([rs274, "-t", table, "-g", base + ".ngc", base + ".full"], stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=30)
        if run.returncode != 0:
            refused += 1
            msg = [l for l in run.stderr.splitlines() if l.strip() and l.strip() != "executing"]
            with open(base + ".err", "w") as f:
                f.write((" / ".join(msg) or f"exit {run.returncode}") + "\n")
        else:
            with open(base + ".full") as f, open(base + ".canon", "w") as g:
                for line in f:
                    i0 = min((line.find(k) for k in KEEP if k in line), default=-1)
                    if i0 >= 0:
                        g.write(line[i0:].rstrip() + "\n")
        if os.path.exists(base + ".full"):
            os.remove(base + ".full")
    print(f"{count} programs, rs274 refused {refused}")


def fixture(out_dir, seed, count):
    """The committed fixture: `count` programs of `seed` without the constructs that differ by design,
    bundled as programs.ngcs (each after a line `%%% NAME`) and rs274.txt (each program's canonical
    lines after `%%% NAME`, or `%%% NAME refused: MESSAGE`)."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["FIXTURE"] = "1"
        sys.argv = [sys.argv[0], tmp, str(seed), str(count)]
        main()
        names = sorted(n[:-4] for n in os.listdir(tmp) if n.endswith(".ngc"))
        with open(os.path.join(out_dir, "programs.ngcs"), "w") as p, open(os.path.join(out_dir, "rs274.txt"), "w") as c:
            for n in names:
                p.write(f"%%% {n}\n" + open(os.path.join(tmp, n + ".ngc")).read())
                err = os.path.join(tmp, n + ".err")
                if os.path.exists(err):
                    c.write(f"%%% {n} refused: {open(err).read().strip()}\n")
                else:
                    c.write(f"%%% {n}\n" + open(os.path.join(tmp, n + ".canon")).read())


if __name__ == "__main__":
    main()

#!/bin/sh
# The motion LinuxCNC's own interpreter makes of these programs, as reference for tests/readers.rs:
# `rs274` (the standalone RS274NGC interpreter of Debian 12's linuxcnc-uspace 2.9.0~pre1) prints its
# canonical machining commands (STRAIGHT_FEED/STRAIGHT_TRAVERSE(x, y, z, a, b, c), 4 decimals).
# The switchkins demos' M428/M429 (remapped kinematics switches, which plain rs274 has no INI for)
# are dropped from rs274's copy: they move nothing.
set -eu
cd "$(dirname "$0")"
for f in cycles expressions offsets xyzac_switchkins_test_1 xyzac_switchkins_test_2; do
    sed -e 's/^M42[89]\b.*$//' "$f.ngc" > "/tmp/$f.rs274.ngc"
    rs274 -g "/tmp/$f.rs274.ngc" "/tmp/$f.canon" < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)' "/tmp/$f.canon" > "$f.canon"
    rm "/tmp/$f.rs274.ngc" "/tmp/$f.canon"
done

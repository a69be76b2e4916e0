#!/bin/sh
# The motion LinuxCNC's own interpreter makes of these programs, as reference for tests/readers.rs:
# `rs274` (the standalone RS274NGC interpreter of Debian 12's linuxcnc-uspace 2.9.0~pre1) prints its
# canonical machining commands (STRAIGHT_FEED/STRAIGHT_TRAVERSE(x, y, z, a, b, c), 4 decimals).
# The switchkins demos' M428/M429 (remapped kinematics switches, which plain rs274 has no INI for)
# are dropped from rs274's copy: they move nothing.
# Where linuxcnc-uspace will not install (its libpcre2-dev dependency held back), rs274 runs from the
# package unpacked: `apt-get download linuxcnc-uspace libboost-python1.74.0`, `dpkg-deb -x` each into a
# directory, LD_LIBRARY_PATH=<dir>/usr/lib:<dir>/usr/lib/x86_64-linux-gnu, and RS274=<dir>/usr/bin/rs274.
set -eu
cd "$(dirname "$0")"
RS274=${RS274:-rs274}
rs274() { "$RS274" "$@"; }
# A tool table: rs274 wants one (a full install has its sample configuration's).
printf 'T1 P1 Z0 D10 ;\n' > /tmp/make_canon.tbl
for f in blanks cycles expressions offsets owords owords_spaces xyzac_switchkins_test_1 xyzac_switchkins_test_2; do
    sed -e 's/^M42[89]\b.*$//' "$f.ngc" > "/tmp/$f.rs274.ngc"
    rs274 -t /tmp/make_canon.tbl -g "/tmp/$f.rs274.ngc" "/tmp/$f.canon" < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)' "/tmp/$f.canon" > "$f.canon"
    rm "/tmp/$f.rs274.ngc" "/tmp/$f.canon"
done
# Axis offsets (G92, G52 and their cancels) and polar coordinates: arcs and units too, so these keep
# ARC_FEED(first_end, second_end, first_centre, second_centre, turn, axis_end, a, b, c) and
# USE_LENGTH_UNITS (rs274 prints positions in the program's unit).
# Cutter radius compensation too (comp_table.ngc takes its diameters from comp.tbl).
for f in offsets_g92 polar polar_cycles comp_lines comp_arcs comp_table comp_g10 cycles_planes; do
    table=/tmp/make_canon.tbl
    case $f in comp_table|comp_g10) table=comp.tbl ;; esac
    rs274 -t "$table" -g "$f.ngc" "/tmp/$f.canon" < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)\|ARC_FEED(.*)\|USE_LENGTH_UNITS(.*)\|SELECT_PLANE(.*)' "/tmp/$f.canon" > "$f.canon"
    rm "/tmp/$f.canon"
done
# Rotated coordinate systems (G10 L2 R): rs274 prints positions in the rotated program frame, so these
# keep the offsets and the rotation it sets too, from which the test places the moves as LinuxCNC's
# canonical layer does (emccanon.cc rotate_and_offset_pos), and the feed (the saved modal state of
# modal_state.ngc's M70-M73 is seen in the moves and feeds after each restore). fanuc_subs and
# fanuc_main_m99 are Fanuc-style subprograms (M98 P L, O<n> ... M99, M99 ending the main program).
for f in rotation offsets_g91 rotation_apart modal_state home state_parameters subs_after fanuc_subs fanuc_main_m99; do
    rs274 -t /tmp/make_canon.tbl -g "$f.ngc" "/tmp/$f.canon" < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)\|ARC_FEED(.*)\|USE_LENGTH_UNITS(.*)\|SELECT_PLANE(.*)\|SET_G5X_OFFSET(.*)\|SET_G92_OFFSET(.*)\|SET_XY_ROTATION(.*)\|SET_FEED_RATE(.*)\|SET_FEED_MODE(.*)' "/tmp/$f.canon" > "$f.canon"
    rm "/tmp/$f.canon"
done
# Feed per revolution (G95): the spindle speeds too, by which the test multiplies a feed per turn.
for f in feed_per_rev; do
    rs274 -t /tmp/make_canon.tbl -g "$f.ngc" "/tmp/$f.canon" < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)\|ARC_FEED(.*)\|USE_LENGTH_UNITS(.*)\|SELECT_PLANE(.*)\|SET_G5X_OFFSET(.*)\|SET_G92_OFFSET(.*)\|SET_XY_ROTATION(.*)\|SET_FEED_RATE(.*)\|SET_FEED_MODE(.*)\|SET_SPINDLE_SPEED(.*)' "/tmp/$f.canon" > "$f.canon"
    rm "/tmp/$f.canon"
done
# Subroutines in files of the subroutine path (subs/, LinuxCNC's [RS274NGC] SUBROUTINE_PATH in an INI).
printf '[RS274NGC]\nSUBROUTINE_PATH = %s/subs\n' "$(pwd)" > /tmp/make_canon.ini
rs274 -i /tmp/make_canon.ini -t /tmp/make_canon.tbl -g calls_files.ngc /tmp/calls_files.canon < /dev/null > /dev/null
grep -o 'STRAIGHT_[A-Z]*(.*)\|ARC_FEED(.*)\|USE_LENGTH_UNITS(.*)\|SELECT_PLANE(.*)' /tmp/calls_files.canon > calls_files.canon
rm /tmp/calls_files.canon /tmp/make_canon.ini
rm /tmp/make_canon.tbl
# LinuxCNC's bridgemill demo (../shared/outside/programs, not committed here) drills a hemisphere in
# nested O-word loops. Standalone rs274 has no W axis (its axis mask is XYZABC), so the W (quill)
# words are taken out of rs274's copy, as tests/readers.rs takes them out of ours; its tool 100 is
# given a table.
shared="../../../../../shared/outside/programs"
f=linuxcnc-rs274ngc_bridgemill-5axisgui-oword
if [ -f "$shared/$f.ngc" ]; then
    sed -E 's/[wW] *(\[[^]]*\]|[-+]?[0-9.]+)//g' "$shared/$f.ngc" > /tmp/bridgemill.rs274.ngc
    printf 'T100 P100 Z0 D10 ;\n' > /tmp/bridgemill.tbl
    rs274 -t /tmp/bridgemill.tbl -g /tmp/bridgemill.rs274.ngc /tmp/bridgemill.canon < /dev/null > /dev/null
    grep -o 'STRAIGHT_[A-Z]*(.*)' /tmp/bridgemill.canon > bridgemill_without_w.canon
    rm /tmp/bridgemill.rs274.ngc /tmp/bridgemill.tbl /tmp/bridgemill.canon
fi

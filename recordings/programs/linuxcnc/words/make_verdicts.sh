#!/bin/sh
# What LinuxCNC's own interpreter says of a line that writes a word twice or two M codes at once, as
# reference for tests/readers/linuxcnc_words.rs: `rs274` (the standalone RS274NGC interpreter of
# Debian 12's linuxcnc-uspace 2.9.0~pre1) runs each case as the third line of a program
# (`G21 G90`, `T1 M6`, the case, `M2`) and its first message, or `ok`, is written beside the case in
# verdicts.tsv. The cases: every letter written twice in a G1 block, and every pair of the M codes
# LinuxCNC reads, each code with itself too, without the words some of them need: rs274 says two
# codes of one modal group before it asks for them.
# Where linuxcnc-uspace will not install, rs274 runs from the package unpacked, as
# ../parameters/make_canon.sh says: RS274=<dir>/usr/bin/rs274 with LD_LIBRARY_PATH set.
set -eu
cd "$(dirname "$0")"
RS274=${RS274:-rs274}
tmp=$(mktemp -d)
printf 'T1 P1 Z0 D10 ;\n' > "$tmp/t.tbl"
verdict() {
    printf 'G21 G90\nT1 M6\n%s\nM2\n' "$1" > "$tmp/p.ngc"
    msg=$("$RS274" -t "$tmp/t.tbl" -g "$tmp/p.ngc" "$tmp/out.canon" < /dev/null 2>&1 | grep -v '^executing$' | grep -v '^$' | head -1 || true)
    printf '%s\t%s\n' "$1" "${msg:-ok}"
}
{
    for l in A B C D E F H I J K L P Q R S T X Y Z; do
        verdict "G1 F100 ${l}1 ${l}2"
    done
    codes="0 1 2 3 4 5 6 7 8 9 19 30 48 49 50 51 52 53 60 61 62 63 64 65 66 67 68 70 71 72 73 100 150 199"
    for a in $codes; do
        for b in $codes; do
            [ "$a" -gt "$b" ] && continue
            verdict "M$a M$b"
        done
    done
} > verdicts.tsv
# Blocks whose words alone LinuxCNC refuses or reads (a G53 or G52/G92 without axes, an arc without
# R I J K, a negative S, a T not a whole number of 0 or more, M61 without Q, a motion code with a
# group 0 code that takes the axes, G1-G3 without F in inverse time, G1 with the feed a G93-G95 zeroed
# or none set yet: the program sets none before; an arc's radius about LinuxCNC's least; M19's R, P
# and Q about their ranges; G86 after the tool change, which stops the spindle; a tool the table,
# which lists T1 alone, has or has not), as the cases of the third line.
{
    for c in "G53" "G0 G53 X1" "G1 G53 X1 F100" "G92" "G92 X0" "G52" "G52 X0" "G92.1" "G2" "G2 F100" \
        "G3 F100" "G2 X10 Y0 I5 F100" "G3 X0 Y10 R10 F100" "S-100" "S0" "S2000" "T-1" "T0.5" "T0" \
        "M61" "M61 Q-1" "M61 Q1" "G1 G92 X0" "G0 G52 X1" "G81 G92 X0 R1 Z-1" "G80 G92 X0" "G80 G10 L2 P1 X0" \
        "G1 G28.1 F100" "G1 G10 L20 P1 X0" "G0 G30" "G0 G28 Z0" "G38.2 G92 X0" "G1 G92.1 F100" \
        "G1" "G1 F100" "G93 G1" "G93 G1 F10" "G93 G3 R5" "G93 G0" "G94 G1" "G94 G1 F100" "G95 G1" \
        "G3 X0 Y0 I0.001 F100" "G3 X0 Y0 I0.0015 F100" "G20 G3 X0 Y0 I0.00004 F10" "G20 G3 X0 Y0 I0.00005 F10" \
        "M19" "M19 R360" "M19 R360.001" "M19 R-10" "M19 P2" "M19 P3" "M19 P1.5" "M19 Q0.001" "M19 Q0" \
        "G98 G86 X1 Y1 Z-1 R2 P0.5 F100" "M3 S1000 G98 G86 X1 Y1 Z-1 R2 P0.5 F100" "T1" "T2"; do
        verdict "$c"
    done
} > blocks.tsv
rm -r "$tmp"

#!/usr/bin/env python3
"""Seed corpora of the fuzz targets, from the repository's own inputs: the NC programs (paper,
LinuxCNC, twins in other dialects, the OCR-damaged copies from ../shared/reference when present),
the small recording fuzz/seeds/small.mcap (rewritten with LZ4, zstd and no compression, and cut
short), its CDR messages, a rosbag2 metadata.yaml, the machines (TOML and URDF) and the roughness
profiles (shortened to 2,000 points, so that each execution stays fast), and MTConnect input: slices of
the Okuma adapter's SHDR log and the agents' device documents of ../shared/outside/mtconnect (read
where they lie beside the clone, never copied here), streams documents and HTTP answers written here.

Usage: seeds.py CORPUS_DIR   (writes CORPUS_DIR/<target>/...; existing files are kept)
"""
import io
import pathlib
import sys
import zipfile

from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer

FUZZ = pathlib.Path(__file__).resolve().parent
ROOT = FUZZ.parent
SHARED = ROOT.parent / "shared" / "reference" / "programs"
PICK = {"heidenhain": 0, "rs274": 1, "cl": 2, "sinumerik": 3, "klartext": 4, "fanuc": 5, "haas": 6}
# Real CAM output (issue 64's corpus), read where it lies beside the clone; never copied here.
OUTSIDE = ROOT.parent / "shared" / "outside" / "programs"
# Program flow as the controls run it (the readers' unit tests' forms): custom macro B with the
# file's subprograms, and the 840D's control structures and jumps.
FANUC_FLOW = (b"%\nO0001\n#1=0\nWHILE [#1 LT 3] DO1\nG1 X[#1*10] F100.\n#1=#1+1\nEND1\nN10 #2=#1*2\n"
              b"IF [#2 GT 100] GOTO 20\n#2=#2+50\nGOTO10\nN20 M98 P1000 L2\nG65 P1000 X1. Y2.\n"
              b"IF [#1 EQ 3] THEN #3=1\nM97 P30\nM30\nN30 G1 Y1.\nM99\nO1000\nG91 G1 X1.\nM99 P40\nN40 G90\nM99\n%\n")
SINUMERIK_FLOW = (b"DEF INT COUNT\nR1=0\nWHILE R1<3\nG1 X=R1*10 F100\nR1=R1+1\nENDWHILE\nFOR COUNT=1 TO 2\n"
                  b"IF COUNT==1\nG1 Y1\nELSE\nG1 Y2\nENDIF\nENDFOR\nMARK1: R2=R1\nREPEAT\nR2=R2-1\nUNTIL R2<=0\n"
                  b"IF R1<2 GOTOB MARK1\nGOTOF DONE\nLOOP\nENDLOOP\nDONE: M30\n")
# Fanuc NURBS curves (G06.2): a rational quarter circle, a cubic with interior knots in least
# increments, an incremental rank-2 polygon, and alarms (a knot missing, knots decreasing).
FANUC_NURBS = (b"%\nO0001\nG21 G17 G90 G94\nG00 X0. Y0. Z0.\nG01 F500.\nG06.2 P3 K0. X0. Y0. Z0. R1. F1000.\n"
               b"K0. X10. Y0. R0.70710678\nK0. X10. Y10. R1.\nK1.\nK1.\nK1.\nG01 X0. Y0.\n"
               b"G06.2 K0 X0. Y0. Z0.\nK0 X10. Y12. Z1. R0.8\nK0 X25. Y-3.\nK0 X32. Y18. R2.5\nK2500 X48.\nK4000 X55. Y2.\n"
               b"K4000 X70. Y9. Z3.\nK10000\nK10000\nK10000\nK10000\nG91 G06.2 P2 K0. X0. Y0.\nK0. X10.\nK1. Y5. R0.5\nK2.\nK2.\n"
               b"G90 G01 X0. Y0.\nG06.2 P3 K0. X0. Y0.\nX5.\nK1.\nK0.5 X1.\nK2.\nK2.\nK2.\nG01 X1.\nM30\n%\n")
# TNC splines (SPL): the iTNC 530 manual's example, a rotary axis with an exponent apart, refusals.
KLARTEXT_SPLINE = (b"0 BEGIN PGM SPL MM\n1 TOOL CALL 1 Z S5000\n2 L X+28.338 Y+19.385 Z-0.5 A+0 FMAX\n"
                   b"3 SPL X24.875 Y15.924 Z-0.5 K3X-4.688E-002 K2X2.459E-002 K1X3.486E+000 K3Y-4.563E-002 K2Y2.155E-002 K1Y3.486E+000 K3Z0.000E+000 K2Z0.000E+000 K1Z0.000E+000 F10000\n"
                   b"4 SPL X+34.875 A+5 K3X+0 K2X+0 K1X-1 E+1 K3A+0 K2A+0 K1A-5\n5 SPL X+40 K2X+0 K3X+0 K1X-5.125\n6 L Z+50 FMAX\n7 END PGM SPL MM\n")
# TNC tilted planes on a machine (the first byte + 7: read on the Hermle): MOVE DIST about the
# point below the tip, TURN MB, STAY with Q120-Q122, RESET.
KLARTEXT_PLANES = (b"0 BEGIN PGM PL MM\n1 TOOL CALL 1 Z S5000\n2 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n"
                   b"3 PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE DIST+30 F1000\n4 L Z+50 R0 FMAX\n"
                   b"5 PLANE SPATIAL SPA+30 SPB+0 SPC+0 TURN MB+20 FMAX SEQ- TABLE ROT\n"
                   b"6 PLANE SPATIAL SPA+0 SPB+0 SPC+0 STAY SEQ+\n7 L A+Q120 C+Q122 R0 FMAX\n"
                   b"8 PLANE RESET STAY\n9 END PGM PL MM\n")
# TNC statements refused whose effect lasts: a rotation cycle and its reset, scaling by a Q parameter,
# PLANE PROJECTED to PLANE RESET, a TCPM form not read to M129.
KLARTEXT_HELD = (b"0 BEGIN PGM HE MM\n1 L X+0 Y+0 Z+10 A+0 C+0 R0 F500\n2 CYCL DEF 10.0 ROTATION\n3 CYCL DEF 10.1 ROT+30\n"
                 b"4 L X+10 RND R2\n5 L Y+10\n6 CYCL DEF 10.1 ROT+0\n7 L Z+20\n8 L X+0 Y+0\n9 CYCL DEF 11.1 SCL+Q5\n"
                 b"10 PLANE PROJECTED PROPR+20 PROMIN+0 ROT+0 TURN FMAX\n11 L X+1 M99\n12 PLANE RESET STAY\n"
                 b"13 FUNCTION TCPM F CONT AXIS POS PATHCTRL AXIS\n14 L X+2 A+5\n15 L M129\n16 L X+0 Y+0 Z+0 A+0 C+0\n17 END PGM HE MM\n")
# Fanuc's refused modal codes held until their cancel: G41 to G40, G51 to G50, G51.1 to G50.1.
FANUC_HELD = (b"%\nO1000\nG21 G90 G17 G94 F100.\nG0 X0. Y0. Z10.\nG41 D1 G1 X10. Y10.\nG1 X20.\nG40 X30. Y0.\n"
              b"G51 X0. Y0. P2\nG1 X2.\nG50\nG51.1 X0.\nX3.\nG50.1\nG1 X4.\nM30\n%\n")
# Additional work offsets set and selected (G10 L20, G54.1 P / G154 P / G110), one refused and held.
FANUC_OFFSETS = (b"%\nG21 G90 G17 G94 F100.\nG10 L20 P1 X100. Y50. Z0.\nG10 L20 P2 X-20. B10.\nG0 X0. Y0. Z10.\n"
                 b"G54.1 P1\nG0 X1.\nG10 L20 P1 X200.\nG54.1 P2 G0 X0.\nG154 P3\nG110 X1.\nG54\nG0 X0. Y0. Z0.\nM30\n%\n")
# The TNC's lasting M functions, an M function not read that the TNC runs, TRANS DATUM.
KLARTEXT_M = (b"0 BEGIN PGM M MM\n1 L X+0 Y+0 Z+50 A+0 C+0 R0 F500\n2 L X+10 M144\n3 L X+20 M145\n4 L X+1 Y+1 Z+1\n"
              b"5 L X+2 M136\n6 L X+3 FMAX\n7 M137\n8 L X+4 M97\n9 M94\n10 L X+0 A+0 C+0\n11 TRANS DATUM RESET\n"
              b"12 TRANS DATUM AXIS X+1\n13 L X+5\n14 TRANS DATUM RESET\n15 L X+0 Y+0 Z+0\n16 END PGM M MM\n")
# The 840D's lasting statements not read and the refused moves the control makes.
SINUMERIK_HELD = (b"G71 G90 G94\nG0 X0 Y0 Z10\nMIRROR X0\nG1 X10 F100\nCYCLE81(10,0,2,-5)\nTRANS\nG1 X1 Y1 Z1\nTRANSMIT\nG1 X2\n"
                  b"TRAFOOF\nORICONCW\nG1 X3\nORIVECT\nFLIN\nG1 X4\nFNORM\nG74 X1=0 Z1=0\nG331 Z-10 K1\nG1 X0 Y0 Z10\n"
                  b"ORIPATH\nORIROTT\nG1 X5\nORIROTA\nORIAXES\nNOSUCH\nCYCLE800(1,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,1,)\nG0 X1 Y2 Z3\nM30\n")
# DIN/ISO transformations and Fanuc's coordinate modes held until their reset.
DIN_HELD = (b"%T G71 *\nN10 T1 G17 S1000 *\nN20 G00 G90 X+0 Y+0 Z+50 *\nN30 G28 X *\nN40 G01 X+10 F500 *\nN50 G28 *\n"
            b"N60 G72 F2 *\nN70 X+3 *\nN80 G72 F1 *\nN90 G73 H+10 *\nN100 X+4 *\nN110 G73 H+0 *\nN120 X+0 Y+0 Z+50 M144 *\nN99999999 %T G71 *\n")
FANUC_MODES = (b"%\nO1\nG21 G90 G17 G94 F100.\nG0 X0. Y0. Z10.\nG16\nG1 X10. Y45.\nG15\nG07.1 C10.\nG1 X1. C5.\nG07.1 C0\n"
               b"G12.1\nG1 X2.\nG13.1\nG31 X5.\nG33 Z-1. F1.\nG0 X0. Y0. Z10.\nM30\n%\n")
# The 840D's circles given otherwise: CIP, AR=, polar coordinates, CT (modal, after a line and an
# arc, a helix, the straight-line limit), a full circle by its centre, and their refusals.
SINUMERIK_CIRCLES = (b"G17 G90 G71 G94\nG0 X30 Y40 Z0\nG1 F100\nCIP X50 Y40 I1=40 J1=45\nG3 X17.203 Y38.029 AR=140.134\n"
                     b"G111 X20 Y10\nG1 RP=50 AP=30\nAP=IC(-90)\nG1 X10 Y0\nCT X20 Y10\nX30 Y20 Z-5\nCT X40 Y20\nCT X45 Y25\n"
                     b"G1 Z5\nCT X0 Y0\nG3 I=AC(0) J=AC(0)\nG18 CT X10 Z5\nG91 CT X5 Y5\nM30\n")
# An 840D contour under tool radius compensation: a tool by name, CFTCP and CFC, arcs by CR, a
# subprogram-free M17 left out, a stop at a CFC outside corner, D0, refusals (KONT, OFFN, G451).
SINUMERIK_TRC = (b"T=\"MILL_D6\" D1\nM6\nG17 G90 G71 G94 CFTCP\nG0 X-20 Y-20 Z5\nG1 Z-2 F500\nG1 G42 X0 Y0\n"
                 b"X60\nG3 X70 Y10 CR=10\nG1 Y40\nZ-3\nM8\nX50\nG2 X40 Y30 CR=10\nCFC\nG1 Y20\nX0\nG40 X-20 Y-10\n"
                 b"T3 D0\nM6\nG41 G1 X0 Y0 KONT\nOFFN=1\nG451\nG41 X5\nX10\nG42 X20\nG40 X30\nM30\n")

# 840D corners: RND, RNDM with FRCM and FRC, CHR and CHF, blocks between, a corner too large, one
# beside an arc, one under G41, the program's end after one.
SINUMERIK_CORNERS = (b"G17 G90 G71 G94\nG0 X0 Y0 Z5\nG1 Z-1 F500\nG1 X50 Y0 RND=5\nM8\nG1 Y30 RNDM=2 FRCM=100\n"
                     b"G1 X0 FRC=50\nG1 Y0 RNDM=0\nG1 X20 CHR=3\nG1 Y10 CHF=2\nG3 X30 Y20 CR=10 RND=60\nG1 X40 CHF=1\n"
                     b"G2 X50 Y10 CR=10\nT1 D1\nM6\nG1 G41 X60 RND=1\nG40 X70\nG1 X80 RND=2\nM30\n")

# Fanuc chamfering and corner R: ,C and ,R between lines and arcs, in a loop, one refused for a block
# between, one too large, ,A, the program's end after one.
FANUC_CORNERS = (b"%\nO0001\nG90 G17 G21 G94\nG00 X10. Y10.\nG01 X50. F100. ,C5.\nY25. ,R8.\nG03 X80. Y55. R30. ,R8.\n"
                 b"G01 X50. ,R8.\nY70. ,C5.\nX10. ,C5\nM08\nY10. ,R90.\n#1=0\nWHILE [#1 LT 2] DO1\nG01 X[20+#1] ,R1.\n"
                 b"Y20.\n#1=#1+1\nEND1\nG01 X0 ,A30.\nG01 Y0 ,C1.\nM30\n%\n")

# A Klartext contour: corners (RND, CHF) under RL with M110, a tool called by name and by number,
# M128's compensating feed, a helix with DR+ written against its F.
KLARTEXT_CONTOUR = (b"0 BEGIN PGM C MM\n1 TOOL CALL \"MILL_D6\" Z S3000\n2 TOOL CALL 3 Z S3000\n3 L X-10 Y+40 Z-2 R0 FMAX\n"
                    b"4 M110\n5 L X+10 Y+40 RL F300\n6 L X+40 Y+25\n7 RND R5 F100\n8 L X+10 Y+5\n9 CHF 2\n10 L X+0 Y+0\n"
                    b"11 CC X+0 Y+10\n12 C X-10 Y+10 DR-\n13 L X-20 Y+10 R0\n14 L M128 F10000\n15 CC X+0 Y+0\n"
                    b"16 CP IPA+90 IZ-1 DR+F200\n17 M111 M116\n18 M117\n19 END PGM C MM\n")


def put(corpus: pathlib.Path, target: str, name: str, data: bytes) -> None:
    d = corpus / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data)


def dialect(path: pathlib.Path, text: bytes) -> str:
    ext = path.suffix.lower()
    if b"BEGIN PGM" in text[:2000].upper():
        return "klartext"
    if ext in (".mpf", ".spf"):
        return "sinumerik"
    name = path.name.lower()
    if name.startswith("haas"):
        return "haas"
    if name.startswith("fanuc"):
        return "fanuc"
    if name.startswith("apt-cl"):
        return "cl"
    if ext in (".i", ".h"):
        return "heidenhain"
    return "rs274"


def programs(corpus: pathlib.Path) -> int:
    files = [p for p in (ROOT / "recordings").rglob("*") if p.suffix.lower() in (".i", ".h", ".ngc", ".nc", ".mpf")]
    if SHARED.is_dir():
        files += [p for p in SHARED.rglob("*") if p.is_file()]
    if OUTSIDE.is_dir():
        files += [p for p in OUTSIDE.iterdir() if p.is_file() and p.name != "SOURCES.md"]
    n = 0
    for p in sorted(files):
        text = p.read_bytes()
        if len(text) > 64 << 10:
            text = text[: 64 << 10]  # the LinuxCNC boat programs: their first 64 KiB
        put(corpus, "nc_program", p.name, bytes([PICK[dialect(p, text)]]) + text)
        n += 1
    put(corpus, "nc_program", "flow.fanuc", bytes([PICK["fanuc"]]) + FANUC_FLOW)
    put(corpus, "nc_program", "flow.haas", bytes([PICK["haas"]]) + FANUC_FLOW)
    put(corpus, "nc_program", "flow.mpf", bytes([PICK["sinumerik"]]) + SINUMERIK_FLOW)
    put(corpus, "nc_program", "contour.h", bytes([PICK["klartext"]]) + KLARTEXT_CONTOUR)
    put(corpus, "nc_program", "spline.h", bytes([PICK["klartext"]]) + KLARTEXT_SPLINE)
    put(corpus, "nc_program", "planes.h", bytes([PICK["klartext"] + len(PICK)]) + KLARTEXT_PLANES)
    put(corpus, "nc_program", "held.nc", bytes([PICK["fanuc"]]) + FANUC_HELD)
    put(corpus, "nc_program", "held.h", bytes([PICK["klartext"] + len(PICK)]) + KLARTEXT_HELD)
    put(corpus, "nc_program", "trc.mpf", bytes([PICK["sinumerik"]]) + SINUMERIK_TRC)
    put(corpus, "nc_program", "circles.mpf", bytes([PICK["sinumerik"]]) + SINUMERIK_CIRCLES)
    put(corpus, "nc_program", "corners.mpf", bytes([PICK["sinumerik"]]) + SINUMERIK_CORNERS)
    put(corpus, "nc_program", "corners.nc", bytes([PICK["fanuc"]]) + FANUC_CORNERS)
    put(corpus, "nc_program", "nurbs.nc", bytes([PICK["fanuc"]]) + FANUC_NURBS)
    put(corpus, "nc_program", "offsets.nc", bytes([PICK["haas"]]) + FANUC_OFFSETS)
    put(corpus, "nc_program", "mfunctions.h", bytes([PICK["klartext"] + len(PICK)]) + KLARTEXT_M)
    put(corpus, "nc_program", "held.mpf", bytes([PICK["sinumerik"]]) + SINUMERIK_HELD)
    put(corpus, "nc_program", "held.i", bytes([PICK["heidenhain"]]) + DIN_HELD)
    put(corpus, "nc_program", "modes.nc", bytes([PICK["fanuc"]]) + FANUC_MODES)
    n += 12
    # CL data: the SING cut's first moves as x y z i j k [feed] lines, with a header, comma and space separated.
    cl = b"x,y,z,i,j,k,f\n0,0,-8,0,0,1,2000\n10,0,-8,0,0.0174,0.9998,2000\n25,0,-8,0,0.0003,1,2000\n50 0 -8 0 0 1\n"
    put(corpus, "nc_program", "sing.cl", bytes([PICK["cl"]]) + cl)
    # APT CL data (read as CL): both CIRCLE forms, a continuation, inches, GODLTA, a refused CUTCOM.
    apt = (b"PARTNO SEED\nMULTAX/ON\nRAPID\nGOTO/5,5,50,0,0,1\nFEDRAT/MMPM,300\nGOTO/30,85,-2.5\n"
           b"CIRCLE/55,85,-2.5,0,0,-1,25\nGOTO/80,85,-2.5\nCIRCLE/95,85,7.5,0,1,0,10,0.01,0.5,10,0\n"
           b"GOTO/95,85,-2.5\nGOTO/105,60,$\n7.5,0.17,0,0.98 $$ tilted\nUNITS/INCHES\nFEDRAT/10,IPM\n"
           b"GODLTA/0,0,0.2\nCUTCOM/LEFT\nEND\nFINI\n")
    put(corpus, "nc_program", "contour.cls", bytes([PICK["cl"]]) + apt)
    return n + 1


def rewrite(src: bytes, compression, chunk: int) -> bytes:
    out = io.BytesIO()
    w = Writer(out, chunk_size=chunk, compression=compression)
    w.start(profile="ros2", library="fiveaxis fuzz seeds")
    schemas, channels = {}, {}
    for schema, channel, m in make_reader(io.BytesIO(src)).iter_messages(log_time_order=False):
        if schema.id not in schemas:
            schemas[schema.id] = w.register_schema(schema.name, schema.encoding, schema.data)
        if channel.id not in channels:
            channels[channel.id] = w.register_channel(channel.topic, channel.message_encoding, schemas[schema.id], channel.metadata)
        w.add_message(channels[channel.id], m.log_time, m.data, m.publish_time, m.sequence)
    w.finish()
    return out.getvalue()


CDR_PICK = {  # cdr_message's first byte: the serde decoders (the DDS path), see fuzz_targets/cdr_message.rs
    "fiveaxis_msgs/msg/AxisState": 2,
    "sensor_msgs/msg/JointState": 3,
    "fiveaxis_msgs/msg/SingularityStatus": 4,
    "diagnostic_msgs/msg/DiagnosticArray": 5,
    "rosgraph_msgs/msg/Clock": 6,
}


def recordings(corpus: pathlib.Path) -> int:
    small = (FUZZ / "seeds" / "small.mcap").read_bytes()
    seeds = {
        "small_zstd.mcap": small,
        "small_lz4.mcap": rewrite(small, CompressionType.LZ4, 4096),
        "small_none.mcap": rewrite(small, CompressionType.NONE, 4096),
    }
    seeds["small_cut.mcap"] = seeds["small_none.mcap"][: len(seeds["small_none.mcap"]) * 2 // 3]
    for name, data in seeds.items():
        put(corpus, "mcap_recording", name, data)
    n = 0
    for schema, channel, m in make_reader(io.BytesIO(small)).iter_messages(log_time_order=False):
        pick = CDR_PICK[schema.name]
        put(corpus, "cdr_message", f"{channel.topic.strip('/').replace('/', '_')}_{m.sequence}", bytes([pick]) + m.data)
        if pick in (2, 3):  # the buffer-reusing readers too (picks 0 and 1)
            put(corpus, "cdr_message", f"{channel.topic.strip('/').replace('/', '_')}_{m.sequence}_reader", bytes([pick - 2]) + m.data)
        n += 1
    # rosbag2's metadata.yaml as `ros2 bag record -s mcap` writes it (version 9), listing the one file.
    meta = """rosbag2_bagfile_information:
  version: 9
  storage_identifier: mcap
  duration:
    nanoseconds: 2000000
  starting_time:
    nanoseconds_since_epoch: 0
  message_count: 21
  topics_with_message_count:
    - topic_metadata:
        name: /fiveaxis/commanded/axis_state
        type: fiveaxis_msgs/msg/AxisState
        serialization_format: cdr
        offered_qos_profiles: "- history: 3\\n  depth: 0\\n  reliability: 1\\n  durability: 2\\n"
        type_description_hash: ""
      message_count: 3
  compression_format: ""
  compression_mode: ""
  relative_file_paths:
    - bag_0.mcap
  files:
    - path: bag_0.mcap
      starting_time:
        nanoseconds_since_epoch: 0
      duration:
        nanoseconds: 2000000
      message_count: 21
  custom_data: ~
  ros_distro: jazzy
"""
    put(corpus, "rosbag2_metadata", "metadata.yaml", meta.encode())
    put(corpus, "rosbag2_metadata", "flow.yaml", b"rosbag2_bagfile_information:\n  storage_identifier: 'mcap'\n  relative_file_paths: [bag_0.mcap]\n")
    return len(seeds) + n + 2


def profiles(corpus: pathlib.Path) -> int:
    rough = ROOT / "recordings" / "roughness"
    csv = (rough / "SYNTHETIC_sing_profile.csv").read_bytes().splitlines(keepends=True)[:2003]
    put(corpus, "csv_profile", "synthetic.csv", b"\0" + b"".join(csv))
    put(corpus, "csv_profile", "bare_mm_um.csv", bytes([2 | (3 << 2)]) + b"0 1.5\n0.001 2.5\n0.002 -1\n0.003 0.5\n")
    with zipfile.ZipFile(rough / "SYNTHETIC_sing_profile.x3p") as z:
        xml = z.read("main.xml").decode()
        data = z.read("bindata/data.bin")
    size = xml.split("<SizeX>")[1].split("</SizeX>")[0]
    xml = xml.replace(f"<SizeX>{size}</SizeX>", "<SizeX>2000</SizeX>").encode()
    data = data[: 2000 * 8]
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("main.xml", xml)
        z.writestr("bindata/data.bin", data)
    put(corpus, "x3p_container", "synthetic.x3p", out.getvalue())
    put(corpus, "x3p_main_xml", "synthetic", xml + b"\0\0" + data)
    listed = xml.replace(b"<DataLink>", b"<!--").replace(b"</DataLink>", b"-->").replace(
        b"</Record3>", b"<DataList>" + b"".join(b"<Datum>%g</Datum>" % (i % 7) for i in range(40)) + b"</DataList></Record3>"
    ).replace(b"<SizeX>2000</SizeX>", b"<SizeX>40</SizeX>")
    put(corpus, "x3p_main_xml", "datalist", listed)
    return 5


def machines(corpus: pathlib.Path) -> int:
    n = 0
    for p in sorted((ROOT / "machines").glob("*.toml")):
        put(corpus, "machine_toml", p.name, p.read_bytes())
        n += 1
    for p in sorted((ROOT / "machines").rglob("*.urdf")):
        put(corpus, "machine_urdf", p.name, p.read_bytes())
        n += 1
    return n

# MTConnect input: a real adapter's SHDR log and agents' device descriptions (read beside the clone).
MTCONNECT = ROOT.parent / "shared" / "outside" / "mtconnect"
# The agent target's first byte: an HTTP answer, a /probe document, a streams document.
AGENT_PICK = {"http": 0, "probe": 1, "streams": 2}
SHDR_WRITTEN = (b"2022-08-08T13:51:34.7167146Z|avail|AVAILABLE|X1actw|12.5|YI1actw|0.25|Z1actw|-3|B1actw|45|C3actw|1.2\n"
                b"* PING\n* shdrVersion: 2\n|X1actw|13\n2022-08-08T13:51:35Z@0.5|OKUMA:Z1actw|-2.5|p1LPathPos|1 2 3\n"
                b"2022-08-08T13:51:35.5+02:00|system|FAULT|E42|HIGH|HIGH|Overtravel|message|M1|hello\n"
                b"2022-08-08T13:51:36Z|@ASSET@|T1|CuttingTool|--multiline--AB\n<CuttingTool/>\n--multiline--AB\n"
                b"2022-08-08T13:51:37Z|@REMOVE_ALL_ASSETS@|CuttingTool\n2022-08-08T13:51:38Z|C3actw|UNAVAILABLE\n")


def streams_document(values, first: int) -> bytes:
    """A streams document of the seeds' device: each (data item id, value) an observation."""
    obs = "".join(f'<Position dataItemId="{i}" timestamp="2022-08-08T13:51:{34 + k:02d}.5Z" sequence="{first + k}">{v}</Position>'
                  for k, (i, v) in enumerate(values))
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<MTConnectStreams xmlns="urn:mtconnect.org:MTConnectStreams:2.0">'
            f'<Header creationTime="2022-08-08T13:51:40Z" instanceId="1660000000" bufferSize="131072" nextSequence="{first + len(values)}" '
            f'firstSequence="1" lastSequence="{first + len(values) - 1}"/><Streams><DeviceStream name="OKUMA" uuid="OKUMA.123456">'
            f'<ComponentStream component="Linear" name="X" componentId="x"><Samples>{obs}</Samples></ComponentStream>'
            f'</DeviceStream></Streams></MTConnectStreams>').encode()


def mtconnect(corpus: pathlib.Path) -> int:
    n = 0
    put(corpus, "shdr_log", "written.txt", SHDR_WRITTEN)
    n += 1
    log = MTCONNECT / "demo_agent_okuma.txt"
    if log.is_file():
        lines = log.read_bytes().splitlines(keepends=True)
        for k, at in enumerate(range(0, len(lines), max(1, len(lines) // 8))):
            put(corpus, "shdr_log", f"okuma_{k}.txt", b"".join(lines[at:at + 60]))
            n += 1
    for p in sorted(MTCONNECT.glob("*.xml")):
        put(corpus, "mtconnect_agent", p.name, bytes([AGENT_PICK["probe"]]) + p.read_bytes())
        n += 1
    a = streams_document([("LX1actw", "12.5"), ("LC3actw", "UNAVAILABLE"), ("LB1actw", "45")], 100)
    b = streams_document([("LZ1actw", "-3"), ("LYI1actw", "0.25")], 103)
    err = (b'<?xml version="1.0"?><MTConnectError xmlns="urn:mtconnect.org:MTConnectError:2.0"><Header instanceId="1" bufferSize="8"/>'
           b'<Errors><Error errorCode="OUT_OF_RANGE">from is out of range</Error></Errors></MTConnectError>')
    put(corpus, "mtconnect_agent", "streams.xml", bytes([AGENT_PICK["streams"]]) + a)
    put(corpus, "mtconnect_agent", "error.xml", bytes([AGENT_PICK["streams"]]) + err)
    part = lambda doc: b"--B1\r\nContent-type: text/xml\r\nContent-length: %d\r\n\r\n%s\r\n" % (len(doc), doc)
    chunk = lambda data: b"%x\r\n%s\r\n" % (len(data), data)
    head = b"HTTP/1.1 200 OK\r\nServer: MTConnectAgent\r\nContent-Type: multipart/mixed;boundary=B1\r\n"
    put(corpus, "mtconnect_agent", "chunked.http", bytes([AGENT_PICK["http"]]) + head + b"Transfer-Encoding: chunked\r\n\r\n"
        + chunk(part(a)) + chunk(part(b)) + b"0\r\n\r\n")
    put(corpus, "mtconnect_agent", "replace.http", bytes([AGENT_PICK["http"]])
        + b"HTTP/1.1 200 OK\r\nContent-Type: multipart/x-mixed-replace; boundary=\"B1\"\r\n\r\npreamble\r\n--B1\r\n\r\n"
        + a + b"\r\n--B1\r\nContent-type: text/xml\r\n\r\n" + b + b"\r\n--B1--\r\n")
    put(corpus, "mtconnect_agent", "current.http", bytes([AGENT_PICK["http"]])
        + b"HTTP/1.1 100 Continue\r\n\r\nHTTP/1.1 200 OK\r\nContent-Length: %d\r\n\r\n%s" % (len(a), a))
    return n + 5


def main() -> int:
    corpus = pathlib.Path(sys.argv[1])
    n = programs(corpus) + recordings(corpus) + profiles(corpus) + machines(corpus) + mtconnect(corpus)
    print(f"{n} seeds in {corpus}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

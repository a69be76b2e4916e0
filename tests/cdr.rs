//! The allocation-free CDR decoder of the offline analysis (`AxisState::read_cdr`,
//! `JointState::read_cdr`) against serde + cdr_encoding, the decoder the DDS transport uses: the same
//! values for any message, little or big endian, and an error (never a panic) wherever serde errs on
//! truncated or damaged bytes.

use fiveaxis::record::{from_cdr, to_cdr};
use fiveaxis_msgs::{AxisState, Header, JointState, Point, Time, Vector3};
use proptest::prelude::*;

fn axis_state() -> impl Strategy<Value = AxisState> {
    (
        (any::<i32>(), any::<u32>(), "[a-z_/]{0,12}", any::<u8>()),
        proptest::collection::vec("[A-Za-z0-9é]{0,6}", 0..7),
        proptest::collection::vec(any::<f64>(), 0..7),
        proptest::collection::vec(any::<f64>(), 0..7),
        proptest::collection::vec(any::<f64>(), 0..7),
        proptest::array::uniform6(any::<f64>()),
        (any::<f64>(), any::<f64>(), any::<u32>(), any::<i64>(), any::<u8>()),
    )
        .prop_map(|((sec, nanosec, frame_id, source), name, position, velocity, acceleration, v, (pf, f, line, block, motion))| AxisState {
            header: Header { stamp: Time { sec, nanosec }, frame_id },
            source,
            name,
            position,
            velocity,
            acceleration,
            tool_tip: Point { x: v[0], y: v[1], z: v[2] },
            tool_axis: Vector3 { x: v[3], y: v[4], z: v[5] },
            programmed_feed: pf,
            path_feed: f,
            program_line: line,
            block_number: block,
            motion,
        })
}

/// Bitwise equality (NaN payloads included), which PartialEq on f64 cannot say.
fn same(a: &AxisState, b: &AxisState) -> bool {
    format!("{a:?}") == format!("{b:?}")
        && a.position.iter().chain(&a.velocity).chain(&a.acceleration).map(|v| v.to_bits()).eq(b.position.iter().chain(&b.velocity).chain(&b.acceleration).map(|v| v.to_bits()))
}

/// The same message in big-endian CDR (CDR_BE), written field by field.
fn to_cdr_be(m: &AxisState) -> Vec<u8> {
    let mut out = vec![0x00, 0x00, 0x00, 0x00];
    let pad = |out: &mut Vec<u8>, n: usize| {
        while !(out.len() - 4).is_multiple_of(n) {
            out.push(0);
        }
    };
    let u32_ = |out: &mut Vec<u8>, v: u32| {
        pad(out, 4);
        out.extend(v.to_be_bytes());
    };
    let f64_ = |out: &mut Vec<u8>, v: f64| {
        pad(out, 8);
        out.extend(v.to_be_bytes());
    };
    let string = |out: &mut Vec<u8>, s: &str| {
        u32_(out, s.len() as u32 + 1);
        out.extend(s.as_bytes());
        out.push(0);
    };
    u32_(&mut out, m.header.stamp.sec as u32);
    u32_(&mut out, m.header.stamp.nanosec);
    string(&mut out, &m.header.frame_id);
    out.push(m.source);
    u32_(&mut out, m.name.len() as u32);
    for n in &m.name {
        string(&mut out, n);
    }
    for seq in [&m.position, &m.velocity, &m.acceleration] {
        u32_(&mut out, seq.len() as u32);
        for v in seq {
            f64_(&mut out, *v);
        }
    }
    for v in [m.tool_tip.x, m.tool_tip.y, m.tool_tip.z, m.tool_axis.x, m.tool_axis.y, m.tool_axis.z, m.programmed_feed, m.path_feed] {
        f64_(&mut out, v);
    }
    u32_(&mut out, m.program_line);
    pad(&mut out, 8);
    out.extend(m.block_number.to_be_bytes());
    out.push(m.motion);
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn axis_state_decodes_as_serde_does(m in axis_state(), warm in axis_state()) {
        let bytes = to_cdr(&m).unwrap();
        // Decode into a value that already holds another message: nothing of it may survive.
        let mut fast = warm;
        fast.read_cdr(&bytes).unwrap();
        let serde: AxisState = from_cdr(&bytes).unwrap();
        prop_assert!(same(&fast, &serde), "{fast:?} != {serde:?}");
        prop_assert!(same(&fast, &m));
        // Big endian: the same values again, by both decoders.
        let be = to_cdr_be(&m);
        let mut fast_be = AxisState::default();
        fast_be.read_cdr(&be).unwrap();
        prop_assert!(same(&fast_be, &m));
        prop_assert!(same(&from_cdr::<AxisState>(&be).unwrap(), &m));
    }

    #[test]
    fn damaged_axis_state_errs_where_serde_errs(m in axis_state(), cut in 0usize..400, flip in 0usize..400, byte in any::<u8>()) {
        let mut bytes = to_cdr(&m).unwrap();
        if flip < bytes.len() {
            bytes[flip] = byte;
        }
        bytes.truncate(cut.min(bytes.len()));
        let mut fast = AxisState::default();
        let fast_result = fast.read_cdr(&bytes);
        // Warm: a value that holds the undamaged message, so that repeated strings are stepped over
        // (the joint names' shortcut); it must read and refuse exactly as the cold one does.
        let mut warm = AxisState::default();
        warm.read_cdr(&to_cdr(&m).unwrap()).unwrap();
        let warm_result = warm.read_cdr(&bytes);
        prop_assert_eq!(&warm_result, &fast_result, "a warm decoder differs from a cold one");
        match from_cdr::<AxisState>(&bytes) {
            Ok(serde) => {
                prop_assert!(fast_result.is_ok(), "fast decoder refused what serde read: {fast_result:?}");
                prop_assert!(same(&fast, &serde));
                prop_assert!(same(&warm, &serde));
            }
            Err(_) => prop_assert!(fast_result.is_err(), "fast decoder read what serde refused"),
        }
    }

    #[test]
    fn joint_state_decodes_as_serde_does(
        name in proptest::collection::vec("[a-z0-9_]{0,8}", 0..6),
        position in proptest::collection::vec(any::<f64>(), 0..6),
        velocity in proptest::collection::vec(-1e3f64..1e3, 0..6),
        effort in proptest::collection::vec(-1e3f64..1e3, 0..3),
        sec in any::<i32>(), cut in 0usize..300,
    ) {
        let m = JointState { header: Header { stamp: Time { sec, nanosec: 7 }, frame_id: "base".into() }, name, position, velocity, effort };
        let bytes = to_cdr(&m).unwrap();
        let mut fast = JointState::default();
        fast.read_cdr(&bytes).unwrap();
        prop_assert_eq!(format!("{fast:?}"), format!("{m:?}"));
        let short = &bytes[..cut.min(bytes.len())];
        prop_assert_eq!(JointState::default().read_cdr(short).is_ok(), from_cdr::<JointState>(short).is_ok());
    }
}

#[test]
fn errors_name_the_field_and_offset() {
    let m = AxisState { position: vec![0.0; 5], ..Default::default() };
    let bytes = to_cdr(&m).unwrap();
    let e = AxisState::default().read_cdr(&bytes[..40]).unwrap_err();
    assert_eq!(e.field, "position");
    assert!(e.offset >= 20 && e.offset <= 40, "{e}");
    assert!(AxisState::default().read_cdr(&[0, 9, 0, 0, 1, 2, 3]).unwrap_err().to_string().contains("encapsulation"));
    // A count far beyond the message is refused before any allocation.
    let mut huge = bytes.clone();
    huge[20..24].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(AxisState::default().read_cdr(&huge).is_err());
}

/// A JointState with `n` joints named `name`, and a frame id.
fn joints(n: usize, name: &str, frame_id: &str) -> JointState {
    JointState {
        header: Header { stamp: Time { sec: 1, nanosec: 0 }, frame_id: frame_id.into() },
        name: vec![name.to_string(); n],
        position: vec![0.5; n.min(300)],
        velocity: vec![],
        effort: vec![],
    }
}

#[test]
fn oversized_joint_states_are_refused_at_their_counts() {
    use fiveaxis_msgs::bounds::{MAX_FRAME_ID_BYTES, MAX_JOINTS, MAX_NAME_BYTES};
    // At the bounds: accepted by both decoders, with the values written.
    let edge = joints(MAX_JOINTS, &"j".repeat(MAX_NAME_BYTES), &"f".repeat(MAX_FRAME_ID_BYTES));
    let bytes = to_cdr(&edge).unwrap();
    assert_eq!(from_cdr::<JointState>(&bytes).unwrap(), edge);
    let mut ours = JointState::default();
    ours.read_cdr(&bytes).unwrap();
    assert_eq!(ours, edge);
    // A million joints (6 MB on the wire, as a hostile bridge could publish it), one joint too
    // many, a name or a frame id one byte too long: both decoders refuse, naming the field (serde's
    // is the one ros2-client uses on DDS samples).
    let cases = [
        (joints(1_000_000, "j", "base"), "name", "joint names"),
        (joints(MAX_JOINTS + 1, "j", "base"), "name", "joint names"),
        (joints(3, &"j".repeat(MAX_NAME_BYTES + 1), "base"), "name", "joint name"),
        (joints(3, "j", &"f".repeat(MAX_FRAME_ID_BYTES + 1)), "header.frame_id", "frame_id"),
        (JointState { position: vec![0.0; MAX_JOINTS + 1], ..joints(3, "j", "base") }, "position", "joint values"),
    ];
    for (m, field, serde_says) in cases {
        let bytes = to_cdr(&m).unwrap();
        let e = from_cdr::<JointState>(&bytes).unwrap_err().to_string();
        assert!(e.contains(serde_says) && e.contains("more than"), "serde: {e}");
        let e = JointState::default().read_cdr(&bytes).unwrap_err();
        assert_eq!(e.field, field, "{e}");
        assert!(e.reason.contains("MAX_"), "{e}");
    }
    // The million is judged at its count (header 4, stamp 8, frame id 4 + 5, aligned to 24), before
    // any name is read.
    let e = JointState::default().read_cdr(&to_cdr(&joints(1_000_000, "j", "base")).unwrap()).unwrap_err();
    assert_eq!((e.field, e.offset), ("name", 24), "{e}");
    // The same bound on our AxisState.
    let st = AxisState { name: vec!["x".into(); MAX_JOINTS + 1], ..Default::default() };
    let bytes = to_cdr(&st).unwrap();
    assert!(from_cdr::<AxisState>(&bytes).is_err());
    assert_eq!(AxisState::default().read_cdr(&bytes).unwrap_err().field, "name");
}

//! Malformed files give typed errors with the line where the problem was noticed, never panics;
//! the quirks real exporters produce are accepted.

use bvh::{parse, ParseErrorKind};

const GOOD: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n1 2 3\n4 5 6\n";

#[test]
fn good_file_parses() {
    let b = parse(GOOD).expect("parses");
    assert_eq!(b.motion.values, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
}

#[test]
fn empty_file() {
    let e = parse("").unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::Empty);
    assert_eq!(e.line, 1);
    assert!(matches!(
        parse(" \n\r\n").unwrap_err().kind,
        ParseErrorKind::Empty
    ));
}

#[test]
fn truncated_in_the_hierarchy() {
    let text = &GOOD[..GOOD.find("End Site").expect("has End Site")];
    let e = parse(text).unwrap_err();
    assert!(
        matches!(e.kind, ParseErrorKind::UnexpectedEof { .. }),
        "{e}"
    );
    assert_eq!(e.line, 6, "{e}");
}

#[test]
fn truncated_in_the_data() {
    let text = GOOD.trim_end_matches("4 5 6\n");
    let e = parse(text).unwrap_err();
    assert_eq!(
        e.kind,
        ParseErrorKind::TooFewValues {
            frames: 2,
            expected: 6,
            found: 3
        }
    );
    assert_eq!(e.line, 15, "{e}");
    assert!(e.to_string().starts_with("line 15"), "{e}");
}

#[test]
fn too_many_values() {
    let e = parse(&format!("{GOOD}7\n")).unwrap_err();
    assert!(
        matches!(e.kind, ParseErrorKind::TooManyValues { .. }),
        "{e}"
    );
    assert_eq!((e.line, e.column), (16, 1));
}

#[test]
fn not_a_number() {
    let e = parse(&GOOD.replace("4 5 6", "4 x5 6")).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::NotANumber("x5".into()));
    assert_eq!((e.line, e.column), (15, 3));
    let e = parse(&GOOD.replace("4 5 6", "4 NaN 6")).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::NotANumber("NaN".into()));
}

#[test]
fn missing_brace() {
    // The joint's opening brace is gone: OFFSET is found where `{` was expected.
    let e = parse(&GOOD.replacen("{\n\tOFFSET 0 0 0", "\tOFFSET 0 0 0", 1)).unwrap_err();
    assert!(matches!(e.kind, ParseErrorKind::Unexpected { .. }), "{e}");
    assert_eq!(e.line, 3, "{e}");
    // The closing brace is gone: MOTION is found inside the joint.
    let e = parse(&GOOD.replace("\t}\n}\n", "\t}\n")).unwrap_err();
    assert!(matches!(e.kind, ParseErrorKind::Unexpected { .. }), "{e}");
    assert_eq!(e.line, 10, "{e}");
}

#[test]
fn unknown_channel_and_bad_counts() {
    let e = parse(&GOOD.replace("Zposition", "Wposition")).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::UnknownChannel("Wposition".into()));
    assert_eq!((e.line, e.column), (5, 33));
    let e = parse(&GOOD.replace("Frames: 2", "Frames: -2")).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::BadCount("-2".into()));
    // Found by the fuzzer: a bad channel count was called a frame count.
    let e = parse(&GOOD.replace("CHANNELS 3", "CHANNELS -")).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::BadChannelCount("-".into()));
    assert_eq!(
        e.to_string(),
        "line 5, column 11: `-` is not a channel count"
    );
}

#[test]
fn a_lying_frame_count_does_not_allocate_it() {
    // Would be 3 × 10^18 values: refused as truncated data, without reserving that much.
    let e = parse(&GOOD.replace("Frames: 2", "Frames: 1000000000000000000")).unwrap_err();
    assert!(matches!(e.kind, ParseErrorKind::TooFewValues { .. }), "{e}");
    let e = parse(&GOOD.replace("Frames: 2", "Frames: 18446744073709551615")).unwrap_err();
    assert!(matches!(e.kind, ParseErrorKind::TooLarge { .. }), "{e}");
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let mut text = String::from("HIERARCHY\nROOT r\n{\n");
    for i in 0..5000 {
        text.push_str(&format!("JOINT j{i}\n{{\n"));
    }
    let e = parse(&text).unwrap_err();
    assert_eq!(e.kind, ParseErrorKind::TooDeep);
}

#[test]
fn exporter_quirks_are_accepted() {
    // CR line ends, `{` on the joint's line, a name with spaces, no space after colons,
    // `.5` and scientific notation, values split across lines, a leaf without End Site, and a
    // second root.
    let text = "HIERARCHY\rROOT My Hips {\r OFFSET 0 0 0\r CHANNELS 3 Xposition Yposition Zposition\r\r JOINT Left Foot{\r  OFFSET 1e0 .5 -2.5E-1\r  CHANNELS 1 Zrotation\r }\r}\rROOT Prop\r{\rOFFSET 0 0 0\rCHANNELS 1 Yrotation\r}\rMOTION\rFrames:2\rFrame Time:.0083333\r1 2\r3 4 5\r6 7 8 9 10\r";
    let b = parse(text).expect("parses");
    let s = &b.skeleton;
    assert_eq!(s.joints.len(), 3);
    assert_eq!(s.joints[0].name, "My Hips");
    assert_eq!(s.joints[1].name, "Left Foot");
    assert_eq!(s.joints[1].offset, [1.0, 0.5, -0.25]);
    assert_eq!(s.joints[1].end_site, None);
    assert_eq!(s.root_count(), 2);
    assert_eq!(s.joints[2].first_channel, 4);
    assert_eq!(b.motion.frames(), 2);
    assert_eq!(b.motion.frame_time, 0.0083333);
    assert_eq!(b.motion.frame(1), &[6.0, 7.0, 8.0, 9.0, 10.0]);
    // And it survives a write/parse round trip.
    assert_eq!(parse(&bvh::write(&b)).expect("reparses"), b);
    // CRLF with tabs after the colons.
    let crlf = GOOD
        .replace('\n', "\r\n")
        .replace("Frames: ", "Frames:\t")
        .replace("Frame Time: ", "Frame Time:\t");
    assert_eq!(parse(&crlf).expect("parses"), parse(GOOD).expect("parses"));
}

#[test]
fn every_prefix_of_a_file_is_an_error_or_a_file_never_a_panic() {
    for end in 0..GOOD.len() {
        let _ = parse(&GOOD[..end]);
    }
}

//! The step rule through the file: on the `../c3d-more` trials where fills checked at the
//! limit in memory came out of the file above it (1.50003×: an integer file's rounding to
//! POINT:SCALE, 32-bit floats elsewhere), every fill as read back steps at most 1.5× the
//! marker's largest recorded step. (HansUniVie's trial has 129 fills in its 26 markers; its
//! 154 bone points, virtual points and muscle lengths are model outputs, not filled; puppeteer's
//! has 170 in its markers (177 before issue 45 item 7's refitted expected errors left 5 more
//! `uncertain`, as hockey's 252 became 251; the third round's evidence, the method leading
//! the fill and the speed beside the gap, left 4 more: 172 → 170, 251 → 250, 130 → 129), its
//! 76 bone points, stored among them, being a segment's axes, and its 14 unlabelled points
//! `*1`… left as recorded.)

use evals::step;

#[test]
fn stored_fills_keep_to_the_step_rule() {
    let Some(dir) = testkit::c3d_more() else {
        return;
    };
    let want = [
        ("PhilD001__biomechZoo__hockey_wristshot009.c3d", 250),
        ("martinfelis__puppeteer__testdata.c3d", 170),
        ("HansUniVie__MuscleLength__test.c3d", 129),
    ];
    // Every trial is read back before any count is compared, so a change shows them all.
    let mut got = Vec::new();
    for (name, _) in want {
        let (n, over, worst) = step::check(&dir.join(name)).expect(name);
        assert!(worst <= 1.5, "{name}: {worst}");
        got.push((name, n));
        assert_eq!(over, 0, "{name}: {n} fills, largest {worst}");
    }
    assert_eq!(got, want);
}

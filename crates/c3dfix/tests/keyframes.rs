//! The keyframe job through the library's door, on real BVH files: the report both fronts
//! print, the rebuilt motion written atomically, and the refusals naming the file.

use bvh::error_metric::Effectors;
use bvh::interp::Interp;
use bvh::keyframes::Target;
use c3dfix::{KeyMethod, KeyframeOptions};
use std::path::PathBuf;

fn options(target: Target, method: KeyMethod) -> KeyframeOptions {
    KeyframeOptions {
        target,
        method,
        interp: Interp::Quat,
        effectors: Effectors::EndSites,
        max_segment: None,
        exact: false,
        output: None,
        force: false,
    }
}

fn sample(name: &str) -> Option<PathBuf> {
    Some(testkit::bvh_samples()?.join(name))
}

#[test]
fn walk_reduced_to_twelve_keys_by_both_methods() {
    let Some(path) = sample("bvhtoolbox_walk01.bvh") else {
        return;
    };
    let b = bvh::read(&path).expect("a corpus file reads");
    let greedy = c3dfix::keyframes(&b, &path, &options(Target::Keys(12), KeyMethod::Greedy))
        .expect("greedy")
        .report;
    let optimal = c3dfix::keyframes(&b, &path, &options(Target::Keys(12), KeyMethod::Optimal))
        .expect("optimal")
        .report;
    for r in [&greedy, &optimal] {
        assert_eq!(r.frames, 101);
        assert_eq!(r.keys.len(), 12);
        assert_eq!(
            (r.keys[0], r.keys[11]),
            (0, 100),
            "first and last frames are keys"
        );
        assert_eq!(r.frame_errors.len(), 101);
        let total: f64 = r.frame_errors.iter().sum();
        assert!((total - r.total_error).abs() <= 1e-9 * total.max(1.0));
    }
    // Dynamic programming never does worse than dropping keys one by one.
    assert!(
        optimal.total_error <= greedy.total_error,
        "{} > {}",
        optimal.total_error,
        greedy.total_error
    );
    assert!(greedy.total_error > 0.0);
    assert_eq!(greedy.search_step, None);
    assert!(!greedy.proven_optimal);
    // The report's JSON names the method as people write it, in the fields' order.
    let json = serde_json::to_string(&greedy).expect("serialises");
    assert!(json.starts_with(r#"{"file":"#), "{json}");
    assert!(
        json.contains(r#""method":"greedy","interp":"quat","effectors":"end-sites","frames":101"#),
        "{json}"
    );
}

#[test]
fn an_error_bound_gives_the_fewest_keys_within_it_and_the_rebuilt_motion_is_written() {
    let Some(path) = sample("fairmotion_sinusoidal.bvh") else {
        return;
    };
    let b = bvh::read(&path).expect("a corpus file reads");
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("rebuilt.bvh");
    let mut opts = options(Target::MaxError(0.5), KeyMethod::Greedy);
    opts.output = Some(out.clone());
    let r = c3dfix::keyframes(&b, &path, &opts).expect("reduce").report;
    assert!(r.rms_distance <= 0.5, "{}", r.rms_distance);
    assert!(
        r.keys.len() >= 2 && r.keys.len() < r.frames,
        "{} keys",
        r.keys.len()
    );
    let rebuilt = bvh::read(&out).expect("the rebuilt motion reads back");
    assert_eq!(rebuilt.motion.frames(), b.motion.frames());
    // A second run does not replace it unless asked, and never writes over its input.
    let again = c3dfix::keyframes(&b, &path, &opts).expect_err("exists");
    assert!(matches!(again, c3dfix::Error::Exists { .. }), "{again}");
    opts.output = Some(path.clone());
    opts.force = true;
    let own = c3dfix::keyframes(&b, &path, &opts).expect_err("own input");
    assert!(
        own.to_string().contains("fairmotion_sinusoidal.bvh"),
        "{own}"
    );
}

#[test]
fn an_impossible_key_count_is_refused_naming_the_file() {
    let Some(path) = sample("fairmotion_sinusoidal.bvh") else {
        return;
    };
    let b = bvh::read(&path).expect("a corpus file reads");
    let e = c3dfix::keyframes(&b, &path, &options(Target::Keys(1), KeyMethod::Greedy))
        .expect_err("one key cannot hold a motion");
    let text = e.to_string();
    assert!(text.starts_with(&path.display().to_string()), "{text}");
    assert!(
        text.contains("1 keys requested, but it must be between 2 and the 120 frames"),
        "{text}"
    );
    assert!("optimal".parse::<KeyMethod>().is_ok() && "best".parse::<KeyMethod>().is_err());
}

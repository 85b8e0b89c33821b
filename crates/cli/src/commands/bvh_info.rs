//! BVH part of `c3dfix info`: joints, channels, frames and rate of a BVH file.

use crate::console::outln;
use std::path::Path;

use serde::Serialize;

#[derive(Serialize)]
struct JointInfo<'a> {
    name: &'a str,
    parent: Option<&'a str>,
    offset: [f64; 3],
    channels: Vec<&'static str>,
    end_site: Option<[f64; 3]>,
}

#[derive(Serialize)]
struct Info<'a> {
    file: String,
    roots: usize,
    joints: Vec<JointInfo<'a>>,
    end_sites: usize,
    channels: usize,
    frames: usize,
    frame_time: f64,
    rate: Option<f64>,
    duration: f64,
}

/// Describe a BVH file on stdout, as text or JSON. Called by `info` for `.bvh` files.
pub fn run(file: &Path, json: bool) -> anyhow::Result<i32> {
    let b = bvh::read(file)?;
    let s = &b.skeleton;
    let joints: Vec<JointInfo> = s
        .joints
        .iter()
        .map(|j| JointInfo {
            name: &j.name,
            parent: j
                .parent
                .and_then(|p| s.joints.get(p))
                .map(|p| p.name.as_str()),
            offset: j.offset,
            channels: j.channels.iter().map(|c| c.name()).collect(),
            end_site: j.end_site,
        })
        .collect();
    let info = Info {
        file: file.display().to_string(),
        roots: s.root_count(),
        end_sites: s.end_site_count(),
        channels: s.channel_count(),
        frames: b.motion.frames(),
        frame_time: b.motion.frame_time,
        rate: b.motion.rate(),
        duration: b.motion.frames() as f64 * b.motion.frame_time,
        joints,
    };
    if json {
        outln!("{}", serde_json::to_string_pretty(&info)?)?;
        return Ok(0);
    }
    outln!("{}: BVH", info.file)?;
    outln!(
        "  {} joints ({} root(s), {} End Sites), {} channels per frame",
        info.joints.len(),
        info.roots,
        info.end_sites,
        info.channels
    )?;
    let rate = info
        .rate
        .map(|r| format!("{r:.3} Hz"))
        .unwrap_or_else(|| "unknown rate".into());
    outln!(
        "  {} frames, frame time {} s ({rate}), {:.3} s",
        info.frames,
        info.frame_time,
        info.duration
    )?;
    // Depth for indentation: parents precede children.
    let mut depth = vec![0usize; s.joints.len()];
    for (i, j) in s.joints.iter().enumerate() {
        if let Some(p) = j.parent {
            depth[i] = depth.get(p).copied().unwrap_or(0) + 1;
        }
        let pad = "  ".repeat(depth[i] + 1);
        let channels: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
        let end = if j.end_site.is_some() {
            " + End Site"
        } else {
            ""
        };
        outln!("{pad}{} [{}]{end}", j.name, channels.join(" "))?;
    }
    Ok(0)
}

#[cfg(test)]
mod tests {
    #[test]
    fn describes_a_small_file() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("two.bvh");
        let text = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition Yposition Zposition\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: 2\nFrame Time: 0.5\n1 2 3\n4 5 6\n";
        std::fs::write(&path, text).expect("write");
        assert_eq!(super::run(&path, false).expect("text"), 0);
        assert_eq!(super::run(&path, true).expect("json"), 0);
        std::fs::write(&path, "HIERARCHY\nROOT\n").expect("write");
        let err = super::run(&path, false).unwrap_err().to_string();
        assert!(err.contains("line 2"), "{err}");
    }
}

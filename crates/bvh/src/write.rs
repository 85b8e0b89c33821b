//! Writing BVH text, mirroring [`crate::parse()`].
//!
//! Numbers are printed with Rust's shortest representation that reads back to the same `f64`,
//! so parse → write → parse is exact.

use std::fmt::Write as _;

use crate::skeleton::{Bvh, Skeleton, Vec3};

/// The BVH text of `bvh` (LF line ends, tab indentation).
pub fn write(bvh: &Bvh) -> String {
    let mut out = String::from("HIERARCHY\n");
    let skeleton = &bvh.skeleton;
    let children = children(skeleton);
    for (i, j) in skeleton.joints.iter().enumerate() {
        if j.parent.is_none() {
            write_joint(&mut out, skeleton, &children, i);
        }
    }
    let m = &bvh.motion;
    let _ = writeln!(
        out,
        "MOTION\nFrames: {}\nFrame Time: {}",
        m.frames, m.frame_time
    );
    if m.channels > 0 {
        for row in m.values.chunks(m.channels) {
            let mut first = true;
            for v in row {
                if !first {
                    out.push(' ');
                }
                first = false;
                let _ = write!(out, "{v}");
            }
            out.push('\n');
        }
    }
    out
}

fn children(skeleton: &Skeleton) -> Vec<Vec<usize>> {
    let mut c = vec![Vec::new(); skeleton.joints.len()];
    for (i, j) in skeleton.joints.iter().enumerate() {
        if let Some(p) = j.parent {
            if let Some(list) = c.get_mut(p) {
                list.push(i);
            }
        }
    }
    c
}

fn write_offset(out: &mut String, indent: &str, o: Vec3) {
    let _ = writeln!(out, "{indent}OFFSET {} {} {}", o[0], o[1], o[2]);
}

/// Depth-first, iteratively (no recursion limit on deep hierarchies).
fn write_joint(out: &mut String, s: &Skeleton, children: &[Vec<usize>], root: usize) {
    enum Step {
        Open(usize, usize),
        Close(usize, usize),
    }
    let mut stack = vec![Step::Open(root, 0)];
    while let Some(step) = stack.pop() {
        match step {
            Step::Open(i, depth) => {
                let j = &s.joints[i];
                let pad = "\t".repeat(depth);
                let kw = if j.parent.is_none() { "ROOT" } else { "JOINT" };
                let _ = writeln!(out, "{pad}{kw} {}\n{pad}{{", j.name);
                write_offset(out, &format!("{pad}\t"), j.offset);
                if !j.channels.is_empty() {
                    let names: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
                    let _ = writeln!(
                        out,
                        "{pad}\tCHANNELS {} {}",
                        j.channels.len(),
                        names.join(" ")
                    );
                }
                stack.push(Step::Close(i, depth));
                for &c in children[i].iter().rev() {
                    stack.push(Step::Open(c, depth + 1));
                }
            }
            Step::Close(i, depth) => {
                let pad = "\t".repeat(depth);
                if let Some(e) = s.joints[i].end_site {
                    let _ = writeln!(out, "{pad}\tEnd Site\n{pad}\t{{");
                    write_offset(out, &format!("{pad}\t\t"), e);
                    let _ = writeln!(out, "{pad}\t}}");
                }
                let _ = writeln!(out, "{pad}}}");
            }
        }
    }
}

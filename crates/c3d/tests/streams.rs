//! Reading from a stream that is not a regular file (a FIFO here): the reader takes what the
//! header and parameters announce and stops, even when the stream goes on, and what it reads
//! is what the same bytes give from a regular file.

use std::io::Write;
use std::path::Path;

/// Read `bytes` followed by `trailing` zero bytes through a FIFO in `dir`.
fn read_through_fifo(dir: &Path, bytes: Vec<u8>, trailing: usize) -> c3d::Result<c3d::C3d> {
    let fifo = dir.join("stream");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo");
    assert!(made.success());
    let path = fifo.clone();
    let writer = std::thread::spawn(move || {
        let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(&path) else {
            return;
        };
        // The reader closes the FIFO when it has enough: writes then fail, and that is fine.
        if f.write_all(&bytes).is_ok() {
            let zeros = vec![0u8; 1 << 16];
            for _ in 0..trailing / zeros.len() {
                if f.write_all(&zeros).is_err() {
                    return;
                }
            }
        }
    });
    // Opening the FIFO meets the writer; once the reader has read what it needs and closed
    // it, the writer's next write fails and it stops.
    let r = c3d::read_file(&fifo);
    writer.join().expect("writer");
    r
}

#[test]
fn a_stream_reads_as_the_file_and_its_excess_is_left_unread() {
    let dir = tempfile::tempdir().unwrap();
    let mut files = testkit::all_c3d_files();
    files.extend(testkit::files_with_ext(
        &testkit::workspace_root().join("sample_c3d"),
        "c3d",
    ));
    let mut n = 0;
    for f in files {
        let bytes = std::fs::read(&f).unwrap();
        let Ok(whole) = c3d::read(bytes.clone()) else {
            continue;
        };
        // 64 MiB of zeros after the file: far more than any of these files announces.
        let s = read_through_fifo(dir.path(), bytes, 64 << 20)
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let (a, b) = (whole.points(), s.points());
        assert_eq!(
            (b.frames(), b.count()),
            (a.frames(), a.count()),
            "{}",
            f.display()
        );
        let bits = |v: &[[f32; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert!(
            bits(&a.xyz) == bits(&b.xyz),
            "{}: points differ",
            f.display()
        );
        assert_eq!(
            s.analog().channels(),
            whole.analog().channels(),
            "{}",
            f.display()
        );
        n += 1;
    }
    assert!(n > 0);
}

#[test]
fn an_endless_stream_that_is_not_c3d_is_refused_at_its_header() {
    let e = c3d::read_file("/dev/zero").unwrap_err().to_string();
    assert!(e.contains("not a C3D file"), "{e}");
}

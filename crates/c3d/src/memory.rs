//! Large buffers backed by huge pages where the system allows it.
//!
//! Reading a big trial touches two fresh allocations of the file's size (its bytes, kept for
//! lossless writing, and the decoded arrays). With 4 KiB pages that is one page fault per
//! 4 KiB — for a 160 MB trial, 80 000 faults, as long as the decoding itself. Asking for
//! transparent huge pages (2 MiB) before the first touch removes nearly all of them. It is
//! only advice: where the kernel does not offer huge pages, nothing changes.

/// Buffers smaller than this are left alone.
const MIN_BYTES: usize = 4 << 20;

/// Advise the kernel to back the untouched allocation at `ptr` (`len` bytes) with huge pages.
#[allow(unused_variables)]
pub(crate) fn advise_huge<T>(ptr: *mut T, len: usize) {
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        if len < MIN_BYTES {
            return;
        }
        let start = (ptr as usize).next_multiple_of(HUGE);
        let end = (ptr as usize + len) & !(HUGE - 1);
        if end > start {
            // SAFETY: madvise only changes how the kernel backs pages of a range this process
            // owns (whole huge pages inside the allocation); it reads or writes no memory.
            unsafe {
                libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
            }
        }
    }
}

/// A zeroed vector of `n` elements, advised onto huge pages before anything touches it.
pub(crate) fn zeroed<T: IsZeroElem>(n: usize) -> Vec<T> {
    // `vec![zero; n]` of a zero-valued primitive allocates zeroed memory directly (calloc's
    // fresh pages, no writes), so the pages are still untouched when advised.
    let mut v = vec![T::zero(); n];
    advise_huge(v.as_mut_ptr(), n * std::mem::size_of::<T>());
    v
}

/// Element types whose zero value is all-zero bits.
pub(crate) trait IsZeroElem: Copy {
    fn zero() -> Self;
}

impl IsZeroElem for f32 {
    fn zero() -> Self {
        0.0
    }
}
impl IsZeroElem for u8 {
    fn zero() -> Self {
        0
    }
}
impl IsZeroElem for [f32; 3] {
    fn zero() -> Self {
        [0.0; 3]
    }
}

/// Read a whole (regular) file into a buffer advised onto huge pages.
pub(crate) fn read_file(mut f: std::fs::File) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let len = f.metadata().map(|m| m.len() as usize).unwrap_or(0);
    let mut buf: Vec<u8> = Vec::new();
    // The size is a hint only (the file may change); read_to_end handles any length.
    if buf.try_reserve_exact(len.saturating_add(1)).is_ok() {
        advise_huge(buf.as_mut_ptr(), buf.capacity());
    }
    f.read_to_end(&mut buf)?;
    Ok(buf)
}

/// A file's bytes: read into memory, or privately mapped (see [`map_file`]).
pub(crate) enum Bytes {
    Owned(Vec<u8>),
    Mapped(memmap2::MmapMut),
}

impl std::ops::Deref for Bytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        match self {
            Bytes::Owned(v) => v,
            Bytes::Mapped(m) => m,
        }
    }
}

impl std::ops::DerefMut for Bytes {
    fn deref_mut(&mut self) -> &mut [u8] {
        match self {
            Bytes::Owned(v) => v,
            Bytes::Mapped(m) => m,
        }
    }
}

impl Clone for Bytes {
    /// A copy in memory (a copy of a mapping is the mapped bytes as they are now).
    fn clone(&self) -> Self {
        Bytes::Owned(self.to_vec())
    }
}

impl std::fmt::Debug for Bytes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self {
            Bytes::Owned(_) => "in memory",
            Bytes::Mapped(_) => "mapped",
        };
        write!(f, "{} bytes {kind}", self.len())
    }
}

/// Files smaller than this are read, not mapped: a mapping costs more than it saves.
const MAP_MIN: u64 = 64 << 10;

/// A regular file's bytes through a private, copy-on-write mapping of it, its pages faulted
/// in up front: no fresh memory to zero and fill, and nothing copied. Writes (samples
/// patched in) go to private copies of the pages they touch; the file is never changed.
///
/// The mapping shows the file as it is: a file that another program truncates while the
/// mapping lives makes the next access to the lost pages fail (SIGBUS), and one it rewrites
/// in place shows the new bytes in pages not yet written here. That suits a command that
/// reads a file and is done within seconds; [`read_file`] suits objects that live long
/// (a library user's, the Python package's). Small files, and files that cannot be mapped,
/// are read instead; so is every file outside Unix, where a mapped file cannot be replaced
/// by renaming another over it (as in-place commands do).
pub(crate) fn map_file(f: std::fs::File) -> std::io::Result<Bytes> {
    let len = f.metadata().map(|m| m.len()).unwrap_or(0);
    if cfg!(unix) && len >= MAP_MIN {
        // SAFETY: a private mapping of a regular file, read-write only for this process's
        // own copy-on-write pages; what concurrent changes to the file do is documented
        // above and is the caller's choice of this function.
        if let Ok(m) = unsafe { memmap2::MmapOptions::new().map_copy(&f) } {
            // Fault every page in with one call, without copying any (Linux 5.14 and later;
            // elsewhere the pages come in as they are first read).
            #[cfg(target_os = "linux")]
            let _ = m.advise(memmap2::Advice::PopulateRead);
            return Ok(Bytes::Mapped(m));
        }
    }
    read_file(f).map(Bytes::Owned)
}

//! Whether two paths hold one recording by their bytes: a digest the model
//! keeps, so that a fitted run is still recognised after it was copied or
//! moved (the same file under another name is `imu::output::same_file`).

use std::fs::File;
use std::hash::Hasher;
use std::io::Read;
use std::path::Path;
use std::sync::{Arc, Mutex, PoisonError};

/// A fingerprint of a file's bytes: FNV-1a 64 and the length
/// (`fnv1a64:0123456789abcdef:1048576`). Not a defence against forgery,
/// only a way to tell one recording from another.
pub fn digest(path: &Path) -> std::io::Result<String> {
    digest_of(&mut File::open(path)?)
}

/// [`digest`] of the bytes `reader` gives, to its end.
pub fn digest_of(reader: &mut dyn Read) -> std::io::Result<String> {
    let mut print = Fingerprint::default();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = reader.read(&mut buf)?;
        if n == 0 {
            return Ok(print.finish());
        }
        print.update(&buf[..n]);
    }
}

/// The state of a [`digest`] over bytes given piece by piece.
#[derive(Default)]
pub struct Fingerprint {
    hasher: fnv::FnvHasher,
    len: u64,
}

impl Fingerprint {
    /// Takes in the next bytes.
    pub fn update(&mut self, bytes: &[u8]) {
        self.hasher.write(bytes);
        self.len += bytes.len() as u64;
    }

    /// The digest of the bytes taken in, as [`digest`] writes it.
    pub fn finish(&self) -> String {
        format!("fnv1a64:{:016x}:{}", self.hasher.finish(), self.len)
    }
}

/// A reader that fingerprints the bytes read through it, so that the digest
/// of an input comes from the very bytes its reader read, in the one pass
/// (a pipe gives them once).
pub struct Digesting<R> {
    inner: R,
    print: Arc<Mutex<Fingerprint>>,
}

impl<R: Read> Digesting<R> {
    /// `inner` read through a fingerprint, and a handle on it to read the
    /// digest from once the reader is done.
    pub fn new(inner: R) -> (Digesting<R>, Arc<Mutex<Fingerprint>>) {
        let print = Arc::new(Mutex::new(Fingerprint::default()));
        (
            Digesting {
                inner,
                print: Arc::clone(&print),
            },
            print,
        )
    }
}

impl<R: Read> Read for Digesting<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        // The lock is only ever held to update or finish, neither of which
        // panics: a poisoned one still holds every byte taken in.
        self.print
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .update(&buf[..n]);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use imu::output::same_file;

    #[test]
    fn a_link_is_the_same_file_and_a_copy_has_the_same_digest() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.txt");
        std::fs::write(&a, "gyro_x\n1\n2\n").unwrap();
        let link = dir.path().join("link.txt");
        std::fs::hard_link(&a, &link).unwrap();
        let copy = dir.path().join("copy.txt");
        std::fs::copy(&a, &copy).unwrap();
        let other = dir.path().join("other.txt");
        std::fs::write(&other, "gyro_x\n1\n3\n").unwrap();
        assert!(same_file(&a, &link));
        assert!(same_file(&a, &dir.path().join(".").join("a.txt")));
        assert!(!same_file(&a, &copy));
        assert!(!same_file(&a, &dir.path().join("missing.txt")));
        assert_eq!(digest(&a).unwrap(), digest(&copy).unwrap());
        assert_ne!(digest(&a).unwrap(), digest(&other).unwrap());
        assert!(digest(&a).unwrap().ends_with(":11"));
    }

    #[test]
    fn a_digest_through_a_reader_is_the_digest_of_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.txt");
        let bytes: Vec<u8> = (0..200_000u32).map(|i| (i * 7 % 251) as u8).collect();
        std::fs::write(&a, &bytes).unwrap();
        let (mut reader, print) = Digesting::new(&bytes[..]);
        // Read in uneven pieces, as a buffered reader does.
        let mut sink = [0u8; 1000];
        while reader.read(&mut sink[..997]).unwrap() > 0 {}
        assert_eq!(print.lock().unwrap().finish(), digest(&a).unwrap());
        assert_ne!(digest_of(&mut &bytes[1..]).unwrap(), digest(&a).unwrap());
    }
}

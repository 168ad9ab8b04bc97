//! Whether two paths hold one recording by their bytes: a digest the model
//! keeps, so that a fitted run is still recognised after it was copied or
//! moved (the same file under another name is `imu::output::same_file`).

use std::fs::File;
use std::hash::Hasher;
use std::io::Read;
use std::path::Path;

/// A fingerprint of a file's bytes: FNV-1a 64 and the length
/// (`fnv1a64:0123456789abcdef:1048576`). Not a defence against forgery,
/// only a way to tell one recording from another.
pub fn digest(path: &Path) -> std::io::Result<String> {
    let mut file = File::open(path)?;
    let mut hasher = fnv::FnvHasher::default();
    let mut buf = vec![0u8; 1 << 16];
    let mut len: u64 = 0;
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            break;
        }
        hasher.write(&buf[..n]);
        len += n as u64;
    }
    Ok(format!("fnv1a64:{:016x}:{len}", hasher.finish()))
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
}

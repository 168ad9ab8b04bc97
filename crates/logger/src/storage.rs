//! Where the log goes, and how it reaches the disk.

use std::fs::File;
use std::io::{self, BufWriter, Write};

/// A log's destination: written through, and made durable on request.
pub trait Storage: Write {
    /// The data written so far reaches the disk (`fdatasync`).
    fn sync_data(&mut self) -> io::Result<()>;
    /// Data and metadata reach the disk (`fsync`), at the end of a run.
    fn sync_all(&mut self) -> io::Result<()>;
}

impl Storage for BufWriter<File> {
    fn sync_data(&mut self) -> io::Result<()> {
        self.get_ref().sync_data()
    }

    fn sync_all(&mut self) -> io::Result<()> {
        self.get_ref().sync_all()
    }
}

/// In memory (tests): nothing to sync.
impl Storage for Vec<u8> {
    fn sync_data(&mut self) -> io::Result<()> {
        Ok(())
    }

    fn sync_all(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl<S: Storage + ?Sized> Storage for &mut S {
    fn sync_data(&mut self) -> io::Result<()> {
        (**self).sync_data()
    }

    fn sync_all(&mut self) -> io::Result<()> {
        (**self).sync_all()
    }
}

//! ROS 2 SQLite3 bags (rosbag2_storage_default_plugins, sqlite3 storage):
//! a `topics` table (id, name, type, serialization_format) and a
//! `messages` table (topic_id, timestamp in ns, data), read in time order.
//!
//! The database is read from the file already opened to tell its format,
//! into SQLite's memory (`sqlite3_deserialize`), not reopened by its path:
//! each input is opened once. That holds the whole file in memory while it
//! is read, so a file larger than imutherm's memory limit for a read
//! ([`imu::table::column_limit`]) is refused by its size before any byte
//! is read.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use rusqlite::{Connection, MAIN_DB};

use crate::error::{LogError, LogErrorKind};
use crate::ros_msgs::{self, Kind};
use crate::streams::{BadMessage, Decoded};

/// Reads the IMU and temperature messages of one `.db3` file into `out`.
///
/// `file` is `path` opened, at its start; `path` names the errors.
pub fn read(path: &Path, file: File, out: &mut Decoded) -> Result<(), LogError> {
    let sql = |e: rusqlite::Error| LogError::new(path, LogErrorKind::Sqlite(e.to_string()));
    let db = in_memory(path, file)?;
    let mut topics: Vec<(i64, String, String, Kind)> = Vec::new();
    {
        let mut st = db
            .prepare("SELECT id, name, type, serialization_format FROM topics")
            .map_err(sql)?;
        let rows = st
            .query_map([], |r| {
                Ok((
                    r.get::<_, i64>(0)?,
                    r.get::<_, String>(1)?,
                    r.get::<_, String>(2)?,
                    r.get::<_, String>(3)?,
                ))
            })
            .map_err(sql)?;
        for row in rows {
            let (id, name, ty, ser) = row.map_err(sql)?;
            if let Some(kind) = ros_msgs::kind_of(&ty).filter(|_| ser == "cdr") {
                topics.push((id, name, ty, kind));
            }
        }
    }
    if topics.is_empty() {
        return Ok(());
    }
    let ids = topics
        .iter()
        .map(|t| t.0.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let mut st = db
        .prepare(&format!(
            "SELECT topic_id, timestamp, data, id FROM messages WHERE topic_id IN ({ids}) ORDER BY timestamp, id"
        ))
        .map_err(sql)?;
    let mut rows = st.query([]).map_err(sql)?;
    let mut n = 0u64;
    let mut decoded = 0u64;
    let mut first_bad: Option<LogError> = None;
    // A row that cannot be read stands alone: it is skipped and counted,
    // and the next row reads. A database whose pages cannot be read stops
    // the reading (`rows.next()`): SQLite gives no resync past them.
    while let Some(row) = rows.next().map_err(sql)? {
        n += 1;
        let row_id = row.get_ref(3).ok().and_then(|v| v.as_i64().ok());
        let at = format!("message {n}");
        let listed = match row_id {
            Some(id) => format!("{at} (row id {id})"),
            None => at.clone(),
        };
        match decode_row(row, &topics, out) {
            Ok(()) => decoded += 1,
            Err(Fault::Sql(why)) => {
                first_bad.get_or_insert_with(|| {
                    LogError::new(path, LogErrorKind::Sqlite(why.clone())).at(at.clone())
                });
                out.bad_messages.push(BadMessage {
                    at: listed,
                    why: format!("SQLite: {why}"),
                    count: 1,
                });
            }
            Err(Fault::Cdr(topic, why)) => {
                first_bad.get_or_insert_with(|| {
                    crate::error::malformed(path, "CDR message", why.clone()).at(format!("{at} on {topic}"))
                });
                out.bad_messages.push(BadMessage {
                    at: format!("{listed} on {topic}"),
                    why: format!("malformed CDR message: {why}"),
                    count: 1,
                });
            }
        }
    }
    // Nothing read: the first fault is the answer, not an empty log.
    match first_bad {
        Some(e) if decoded == 0 => Err(e),
        _ => Ok(()),
    }
}

/// The database of `file`, read whole into memory, read-only.
fn in_memory(path: &Path, file: File) -> Result<Connection, LogError> {
    let sql = |e: rusqlite::Error| LogError::new(path, LogErrorKind::Sqlite(e.to_string()));
    let bytes = file.metadata().map_err(|e| LogError::new(path, e.into()))?.len();
    // Unbounded, a read still cannot take more than the address space.
    let addressable = u64::try_from(usize::MAX).unwrap_or(u64::MAX);
    let limit = imu::table::column_limit().map_or(addressable, |l| l.min(addressable));
    if bytes > limit {
        return Err(LogError::new(
            path,
            LogErrorKind::DatabaseTooLarge { bytes, limit },
        ));
    }
    let size = usize::try_from(bytes).unwrap_or(usize::MAX);
    let mut file = file;
    let mut header = [0u8; 100];
    file.read_exact(&mut header)
        .map_err(|e| LogError::new(path, e.into()))?;
    // A bag written in WAL mode (rosbag2's "resilient" preset) says so in
    // its header's file-format bytes (sqlite.org/fileformat.html, 1.3.3:
    // offsets 18 and 19 are 2). A database in memory has no log beside
    // it, and SQLite refuses to open one marked WAL there: once its log is
    // folded in (the recorder closed the bag), its pages are all in the
    // file, and read as a rollback-journal database. A log still beside
    // it holds messages the file lacks: refused, not read without them.
    if header[18] == 2 || header[19] == 2 {
        let mut wal = path.as_os_str().to_owned();
        wal.push("-wal");
        if std::fs::metadata(&wal).is_ok_and(|m| m.len() > 0) {
            return Err(LogError::new(path, LogErrorKind::UnfoldedLog(wal.into())));
        }
        header[18] = 1;
        header[19] = 1;
    }
    let mut db = Connection::open_in_memory().map_err(sql)?;
    db.deserialize_read_exact(MAIN_DB, (&header[..]).chain(file), size, true)
        .map_err(sql)?;
    Ok(db)
}

/// Why a row was not read.
enum Fault {
    /// A value of the wrong type, or one SQLite could not give.
    Sql(String),
    /// The message's bytes, on its topic.
    Cdr(String, String),
}

/// Decodes one row of the messages table into `out`, each value's column
/// and type named: "Invalid type" alone says nothing of where.
fn decode_row(
    row: &rusqlite::Row<'_>,
    topics: &[(i64, String, String, Kind)],
    out: &mut Decoded,
) -> Result<(), Fault> {
    let column = |k: usize, name: &str, wanted: &str| -> Result<rusqlite::types::ValueRef<'_>, Fault> {
        let v = row.get_ref(k).map_err(|e| Fault::Sql(e.to_string()))?;
        let ok = match wanted {
            "INTEGER" => matches!(v, rusqlite::types::ValueRef::Integer(_)),
            _ => matches!(v, rusqlite::types::ValueRef::Blob(_)),
        };
        if ok {
            Ok(v)
        } else {
            Err(Fault::Sql(format!(
                "the {name} column of the messages table holds {:?}, not {wanted}",
                v.data_type()
            )))
        }
    };
    let id = column(0, "topic_id", "INTEGER")?.as_i64().unwrap_or_default();
    let t = column(1, "timestamp", "INTEGER")?.as_i64().unwrap_or_default();
    let data = column(2, "data", "BLOB")?.as_blob().unwrap_or_default();
    if let Some((_, name, ty, kind)) = topics.iter().find(|t| t.0 == id) {
        ros_msgs::add(out, *kind, name, ty, data, t as f64 * 1e-9, false)
            .map_err(|what| Fault::Cdr(name.clone(), what))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bag of rosbag2's schema in WAL mode, its connection left open (its
    /// log not yet folded in) or closed.
    fn wal_bag(dir: &Path, close: bool) -> (std::path::PathBuf, Option<Connection>) {
        let p = dir.join("bag.db3");
        let db = Connection::open(&p).unwrap();
        db.query_row("PRAGMA journal_mode=WAL", [], |_| Ok(())).unwrap();
        db.execute_batch(
            "PRAGMA wal_autocheckpoint=0;
             CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);
             CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);
             INSERT INTO topics VALUES (1, '/chatter', 'std_msgs/msg/String', 'cdr');",
        )
        .unwrap();
        if close {
            drop(db);
            return (p, None);
        }
        (p, Some(db))
    }

    #[test]
    fn a_closed_wal_bag_is_read_from_its_file_alone() {
        let dir = tempfile::tempdir().unwrap();
        let (p, _) = wal_bag(dir.path(), true);
        let mut head = [0u8; 20];
        File::open(&p).unwrap().read_exact(&mut head).unwrap();
        assert_eq!(head[18..20], [2, 2], "the bag is in WAL mode");
        let mut out = Decoded::default();
        read(&p, File::open(&p).unwrap(), &mut out).unwrap();
        assert!(out.imu.is_empty() && out.bad_messages.is_empty());
    }

    #[test]
    fn a_bag_whose_log_is_not_folded_in_is_refused_naming_the_log() {
        let dir = tempfile::tempdir().unwrap();
        let (p, open) = wal_bag(dir.path(), false);
        assert!(open.is_some());
        let e = read(&p, File::open(&p).unwrap(), &mut Decoded::default()).unwrap_err();
        assert!(
            matches!(&e.kind, LogErrorKind::UnfoldedLog(w) if w.ends_with("bag.db3-wal")),
            "{e}"
        );
    }
}

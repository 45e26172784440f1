//! A claim on one entry of the shared reference cache, so that shards running at once (a Slurm
//! array sharing `--cache`) render a missing reference once: the first creates `<entry>.lock`
//! (`create_new`, atomic on local and NFSv3+ file systems), renders, writes the entry atomically
//! (temporary file, then rename) and removes the lock; the others wait and then read the entry.
//!
//! The lock file says who holds it (`pid=`, `host=`, `nonce=`). Its holder refreshes its
//! modification time every [`HEARTBEAT`]; a lock is stale, and taken over, when its holder is a
//! process of this host that no longer exists, or when it has gone [`STALE_AFTER`] without a
//! heartbeat (a holder killed on another host). A waiter therefore never waits for ever on a dead
//! shard, while a live one may render for as long as it needs.
//!
//! Taking over a stale lock re-reads it just before removing it and leaves it if it changed; two
//! waiters judging the same dead lock stale in the same instant could still both render (the
//! original harm, work done twice), never corrupt the entry, which is only ever renamed into place.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, SystemTime};

/// How long a lock may go without its holder's heartbeat before it is taken as abandoned.
pub const STALE_AFTER: Duration = Duration::from_secs(10 * 60);

/// How often a holder refreshes its lock's modification time.
pub const HEARTBEAT: Duration = Duration::from_secs(30);

/// Who holds a lock, as its file says, and how long since its last heartbeat.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Holder {
    pub pid: Option<u32>,
    pub host: String,
    /// The whole file: compared again before a stale lock is removed.
    pub text: String,
    pub age: Duration,
}

impl std::fmt::Display for Holder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.pid {
            Some(pid) => write!(f, "pid {pid} on {}", if self.host.is_empty() { "?" } else { &self.host })?,
            None => write!(f, "an unnamed holder")?,
        }
        write!(f, ", last heartbeat {:.0} s ago", self.age.as_secs_f64())
    }
}

/// The outcome of [`try_claim`].
pub enum Claim {
    /// This process holds the lock until the value is dropped.
    Mine(CacheLock),
    /// A live holder has it: wait, then look for the entry again.
    Held(Holder),
}

/// A held lock: heartbeats while alive, removed on drop.
pub struct CacheLock {
    path: PathBuf,
    stop: Option<Sender<()>>,
    heartbeat: Option<JoinHandle<()>>,
}

impl CacheLock {
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for CacheLock {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(h) = self.heartbeat.take() {
            let _ = h.join();
        }
        if let Err(e) = std::fs::remove_file(&self.path) {
            log::warn!("cannot remove the reference lock {}: {e}", self.path.display());
        }
    }
}

/// `<entry>.lock` beside `entry`.
pub fn lock_path(entry: &Path) -> PathBuf {
    let mut name = entry.file_name().unwrap_or_default().to_os_string();
    name.push(".lock");
    entry.with_file_name(name)
}

/// This machine's name, as locks record it.
pub fn host_name() -> String {
    ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok().map(|s| s.trim().to_string()).filter(|s| !s.is_empty()))
        .unwrap_or_default()
}

/// The text a lock file holds for process `pid` on `host`.
pub fn lock_text(pid: u32, host: &str) -> String {
    let nonce = SystemTime::now().duration_since(SystemTime::UNIX_EPOCH).unwrap_or_default().as_nanos();
    format!("pid={pid}\nhost={host}\nnonce={nonce}\n")
}

/// Claims `lock` for this process, taking over a stale one (`stale_after` without a heartbeat,
/// or a holder on this host that has exited); `Held` when a live holder has it.
pub fn try_claim(lock: &Path, stale_after: Duration) -> io::Result<Claim> {
    // A few rounds: the holder may remove its lock between our create and our read.
    for _ in 0..8 {
        match OpenOptions::new().write(true).create_new(true).open(lock) {
            Ok(mut file) => {
                file.write_all(lock_text(std::process::id(), &host_name()).as_bytes())?;
                file.sync_all()?;
                return Ok(Claim::Mine(CacheLock::start(lock.to_owned(), file)));
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                let Some(holder) = read_holder(lock)? else { continue };
                match stale_reason(&holder, stale_after) {
                    None => return Ok(Claim::Held(holder)),
                    Some(why) => {
                        // Only the lock judged stale: a new holder's lock has another nonce.
                        if read_holder(lock)?.is_some_and(|h| h.text == holder.text) {
                            eprintln!(
                                "taking over the stale reference lock {} ({holder}): {why}",
                                lock.display()
                            );
                            match std::fs::remove_file(lock) {
                                Ok(()) => {}
                                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                                Err(e) => return Err(e),
                            }
                        }
                    }
                }
            }
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other(format!("{}: the lock kept changing hands", lock.display())))
}

/// Why `holder`'s lock is abandoned, or `None` if it may still be rendering.
pub fn stale_reason(holder: &Holder, stale_after: Duration) -> Option<String> {
    if holder.age > stale_after {
        return Some(format!("no heartbeat for over {} s", stale_after.as_secs()));
    }
    let here = host_name();
    if let Some(pid) = holder.pid {
        if !here.is_empty() && holder.host == here && process_gone(pid) {
            return Some(format!("process {pid} on this host has exited"));
        }
    }
    None
}

/// Whether `pid` no longer exists (Linux: no `/proc/PID`); `false` where that cannot be told.
fn process_gone(pid: u32) -> bool {
    Path::new("/proc/self").exists() && !Path::new(&format!("/proc/{pid}")).exists()
}

/// The holder a lock file names; `None` when the file is gone.
pub fn read_holder(lock: &Path) -> io::Result<Option<Holder>> {
    let read =
        std::fs::read_to_string(lock).and_then(|text| Ok((text, std::fs::metadata(lock)?.modified()?)));
    let (text, modified) = match read {
        Ok(r) => r,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e),
    };
    let field = |k: &str| text.lines().find_map(|l| l.strip_prefix(k)?.strip_prefix('=')).map(str::trim);
    Ok(Some(Holder {
        pid: field("pid").and_then(|p| p.parse().ok()),
        host: field("host").unwrap_or("").to_string(),
        age: SystemTime::now().duration_since(modified).unwrap_or_default(),
        text,
    }))
}

impl CacheLock {
    fn start(path: PathBuf, file: File) -> Self {
        let (stop, stopped) = mpsc::channel::<()>();
        let heartbeat = std::thread::spawn(move || loop {
            match stopped.recv_timeout(HEARTBEAT) {
                Err(RecvTimeoutError::Timeout) => {
                    let _ = file.set_modified(SystemTime::now());
                }
                _ => return,
            }
        });
        Self { path, stop: Some(stop), heartbeat: Some(heartbeat) }
    }
}

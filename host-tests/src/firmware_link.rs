//! Host driver for `firmware-example` running in QEMU (`mps2-an386`).
//!
//! (Over 600 lines: building, booting and talking to the firmware, and its defmt log, are one
//! driver; its tests are in `tests/firmware_link.rs`.)
//!
//! [`FirmwareLink::boot`] builds the firmware (`cargo build --release` in `firmware-example`,
//! once per process), starts `qemu-system-arm` with UART0 on a loopback TCP port and
//! semihosting on, connects, and waits for the firmware's `Hello`. Then [`FirmwareLink::send`]
//! / [`FirmwareLink::recv`] exchange frames with timeouts, and helpers ([`FirmwareLink::ping`],
//! [`FirmwareLink::stats`], [`FirmwareLink::cost`]) wrap the link-level messages. QEMU is
//! killed when the link is dropped. Its stdout (the binary defmt log) and stderr are captured;
//! [`FirmwareLink::log`] decodes the defmt log with `defmt-print` when it is installed
//! (`cargo install defmt-print --locked`) and every error message carries that log.
//!
//! [`BootOptions::icount`] runs QEMU with `-icount shift=0`: one instruction = 1 ns of virtual
//! time, SysTick at 25 MHz = 40 instructions per tick, so `Cost` tick counts repeat exactly.

use std::io::{Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU16, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use rotorid_link::msg::{CostReport, CostRequest, Hello, MsgType, Payload, StatsReport, Workload};
use rotorid_link::{
    encode_frame, EncodeError, Feed, FrameDecoder, FrameEncoder, LinkStats, Writer, MAX_PAYLOAD,
    MAX_WIRE_LEN,
};

/// Default time to wait for one reply.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(10);
/// Time QEMU gets to start listening on its serial port.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(20);

/// Why the firmware could not be built. Shared ([`Arc`]) by every [`build_firmware`] call of
/// the process: the build runs once.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    /// `cargo` could not be run.
    #[error("building firmware-example: cannot run cargo")]
    Cargo(#[source] std::io::Error),
    /// `cargo build` ran and failed.
    #[error("building firmware-example failed:\n{log}")]
    Failed {
        /// cargo's error output.
        log: String,
    },
}

/// Errors of the firmware link. Variants that involve QEMU carry its decoded log.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LinkError {
    /// The firmware could not be built.
    #[error(transparent)]
    Build(Arc<BuildError>),
    /// QEMU could not be started (or no local port was free for its serial socket).
    #[error("cannot start qemu-system-arm (is it installed?)")]
    Spawn(#[source] std::io::Error),
    /// QEMU exited or never listened on its serial port.
    #[error("cannot connect to QEMU's serial port: {reason}\n--- firmware log ---\n{log}")]
    Connect {
        /// What went wrong.
        reason: String,
        /// QEMU's output.
        log: String,
    },
    /// Socket I/O failed. The I/O error is part of the message, not a `source`, so that the
    /// firmware log stays last when the error is printed with its causes.
    #[error("serial socket: {error}\n--- firmware log ---\n{log}")]
    Io {
        /// The I/O error.
        error: std::io::Error,
        /// QEMU's output.
        log: String,
    },
    /// No complete frame arrived in time.
    #[error("timed out after {waited:?} waiting for {what}\n--- firmware log ---\n{log}")]
    Timeout {
        /// What was awaited.
        what: String,
        /// How long.
        waited: Duration,
        /// QEMU's output.
        log: String,
    },
    /// A frame could not be encoded.
    #[error("encoding a frame")]
    Encode(#[from] EncodeError),
    /// The firmware answered something unexpected.
    #[error("protocol: {what}\n--- firmware log ---\n{log}")]
    Protocol {
        /// What was wrong.
        what: String,
        /// QEMU's output.
        log: String,
    },
}

/// How to start QEMU.
#[derive(Clone, Debug, Default)]
pub struct BootOptions {
    /// Run with `-icount shift=0` (deterministic instruction-counted time).
    pub icount: bool,
    /// Extra QEMU arguments.
    pub extra_args: Vec<String>,
}

impl BootOptions {
    /// Options for deterministic cost measurement.
    pub fn icount() -> Self {
        Self {
            icount: true,
            ..Self::default()
        }
    }
}

/// One received frame, owned.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OwnedFrame {
    /// Message type code.
    pub msg_type: u8,
    /// Firmware's sequence number.
    pub seq: u16,
    /// Payload.
    pub payload: Vec<u8>,
}

impl OwnedFrame {
    /// The message type, if known.
    pub fn kind(&self) -> Option<MsgType> {
        MsgType::from_u8(self.msg_type)
    }
}

/// What the firmware announced at boot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HelloInfo {
    /// Protocol version.
    pub version: u8,
    /// Largest payload it accepts, in bytes.
    pub max_payload: u16,
    /// Feature flags (bit 0: fault injection hook).
    pub flags: u8,
    /// Firmware name.
    pub name: String,
}

/// Path of the `firmware-example` crate.
pub fn firmware_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("firmware-example")
}

/// Builds the firmware in release mode (once per process) and returns the ELF path.
///
/// The child cargo gets a clean environment for target selection: `CARGO_TARGET_DIR`,
/// `RUSTFLAGS` and friends of the host build would otherwise leak into the MCU build.
pub fn build_firmware() -> Result<PathBuf, LinkError> {
    static BUILT: OnceLock<Result<PathBuf, Arc<BuildError>>> = OnceLock::new();
    BUILT
        .get_or_init(|| {
            let dir = firmware_dir();
            let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
            let out = Command::new(cargo)
                .args(["build", "--release", "--quiet"])
                .current_dir(&dir)
                .env_remove("CARGO_TARGET_DIR")
                .env_remove("RUSTFLAGS")
                .env_remove("CARGO_ENCODED_RUSTFLAGS")
                .env_remove("CARGO_BUILD_TARGET")
                .env_remove("CARGO_BUILD_RUSTFLAGS")
                .env_remove("CARGO_MANIFEST_DIR")
                .output()
                .map_err(|e| Arc::new(BuildError::Cargo(e)))?;
            if !out.status.success() {
                return Err(Arc::new(BuildError::Failed {
                    log: String::from_utf8_lossy(&out.stderr).into_owned(),
                }));
            }
            Ok(dir.join("target/thumbv7em-none-eabihf/release/firmware-example"))
        })
        .clone()
        .map_err(LinkError::Build)
}

/// Builds the firmware (with its `step-cost` binary) and returns a `qemu-system-arm` command
/// that runs `step-cost` on `mps2-an386` with `-icount shift=0` (one SysTick tick = 40
/// instructions) and semihosting on, the serial port and monitor off; add `-append` arguments
/// or trace options before running it.
pub fn step_cost_qemu() -> Result<Command, LinkError> {
    build_firmware()?;
    let mut cmd = Command::new("qemu-system-arm");
    cmd.args([
        "-cpu",
        "cortex-m4",
        "-machine",
        "mps2-an386",
        "-display",
        "none",
    ])
    .args(["-monitor", "none", "-serial", "null", "-icount", "shift=0"])
    .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
    .arg(step_cost_elf());
    Ok(cmd)
}

/// The ELF of `firmware-example`'s `step-cost` binary (built by [`step_cost_qemu`]).
pub fn step_cost_elf() -> PathBuf {
    firmware_dir().join("target/thumbv7em-none-eabihf/release/step-cost")
}

/// Finds `defmt-print` on `PATH` or in cargo's bin folder.
fn defmt_print() -> Option<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).collect())
        .unwrap_or_default();
    if let Some(home) = std::env::var_os("CARGO_HOME") {
        dirs.push(PathBuf::from(home).join("bin"));
    }
    if let Some(home) = std::env::var_os("HOME") {
        dirs.push(PathBuf::from(home).join(".cargo/bin"));
    }
    dirs.into_iter()
        .map(|d| d.join("defmt-print"))
        .find(|p| p.is_file())
}

/// Decodes a raw defmt byte stream from `elf` into text (or explains why it cannot).
pub fn decode_defmt(elf: &Path, raw: &[u8]) -> String {
    if raw.is_empty() {
        return String::from("(no defmt output)");
    }
    let Some(tool) = defmt_print() else {
        return format!(
            "({} bytes of binary defmt log; `cargo install defmt-print --locked` to decode)",
            raw.len()
        );
    };
    let child = Command::new(tool)
        .arg("-e")
        .arg(elf)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return format!("(defmt-print failed to start: {e})"),
    };
    if let Some(mut stdin) = child.stdin.take() {
        // defmt-print stops at EOF; an error here shows up in its output.
        let _ = stdin.write_all(raw);
    }
    match child.wait_with_output() {
        Ok(o) => {
            let mut s = String::from_utf8_lossy(&o.stdout).into_owned();
            s.push_str(&String::from_utf8_lossy(&o.stderr));
            s
        }
        Err(e) => format!("(defmt-print failed: {e})"),
    }
}

fn capture(mut r: impl Read + Send + 'static, sink: Arc<Mutex<Vec<u8>>>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = r.read(&mut buf) {
            if n == 0 {
                break;
            }
            if let Ok(mut s) = sink.lock() {
                s.extend_from_slice(&buf[..n]);
            }
        }
    })
}

/// A running firmware in QEMU and the host end of its telemetry link.
pub struct FirmwareLink {
    child: Child,
    stream: TcpStream,
    elf: PathBuf,
    stdout: Arc<Mutex<Vec<u8>>>,
    stderr: Arc<Mutex<Vec<u8>>>,
    readers: Vec<JoinHandle<()>>,
    decoder: FrameDecoder,
    /// Received bytes not yet fed to the decoder.
    pending: Vec<u8>,
    tx: FrameEncoder,
    hello: HelloInfo,
    /// Timeout of [`FirmwareLink::recv`].
    pub timeout: Duration,
}

impl FirmwareLink {
    /// Builds and boots the firmware with default options.
    pub fn boot() -> Result<Self, LinkError> {
        Self::boot_with(&BootOptions::default())
    }

    /// Builds and boots the firmware under `-icount shift=0`.
    pub fn boot_icount() -> Result<Self, LinkError> {
        Self::boot_with(&BootOptions::icount())
    }

    /// Builds and boots the firmware. A boot that fails before the firmware's Hello (QEMU could
    /// not bind its port, the connection was reset, the handshake timed out on a loaded
    /// machine) is retried with a new port, up to [`BOOT_ATTEMPTS`] times.
    pub fn boot_with(opts: &BootOptions) -> Result<Self, LinkError> {
        let elf = build_firmware()?;
        let mut attempt = 1;
        loop {
            match Self::start(&elf, opts) {
                Err(
                    e @ (LinkError::Connect { .. }
                    | LinkError::Io { .. }
                    | LinkError::Timeout { .. }
                    | LinkError::Protocol { .. }),
                ) if attempt < BOOT_ATTEMPTS => {
                    eprintln!("firmware boot attempt {attempt} failed, retrying: {e}");
                    attempt += 1;
                }
                r => return r,
            }
        }
    }

    fn start(elf: &Path, opts: &BootOptions) -> Result<Self, LinkError> {
        let port = pick_port().map_err(LinkError::Spawn)?;
        let mut cmd = Command::new("qemu-system-arm");
        cmd.args(["-cpu", "cortex-m4", "-machine", "mps2-an386"])
            .args(["-display", "none", "-monitor", "none"])
            .args(["-semihosting-config", "enable=on,target=native"])
            .arg("-serial")
            .arg(format!("tcp:127.0.0.1:{port},server=on,wait=on,nodelay=on"));
        if opts.icount {
            cmd.args(["-icount", "shift=0"]);
        }
        cmd.args(&opts.extra_args)
            .arg("-kernel")
            .arg(elf)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = cmd.spawn().map_err(LinkError::Spawn)?;
        let stdout = Arc::new(Mutex::new(Vec::new()));
        let stderr = Arc::new(Mutex::new(Vec::new()));
        let mut readers = Vec::new();
        if let Some(o) = child.stdout.take() {
            readers.push(capture(o, stdout.clone()));
        }
        if let Some(e) = child.stderr.take() {
            readers.push(capture(e, stderr.clone()));
        }
        let log_now = |child: &mut Child| {
            let _ = child.kill();
            let _ = child.wait();
            let err = stderr.lock().map(|s| s.clone()).unwrap_or_default();
            let out = stdout.lock().map(|s| s.clone()).unwrap_or_default();
            format!(
                "{}\n{}",
                decode_defmt(elf, &out),
                String::from_utf8_lossy(&err)
            )
        };
        let addr = SocketAddr::from((Ipv4Addr::LOCALHOST, port));
        let t0 = Instant::now();
        let stream = loop {
            match TcpStream::connect_timeout(&addr, Duration::from_millis(500)) {
                Ok(s) => break s,
                Err(e) => {
                    if let Ok(Some(status)) = child.try_wait() {
                        return Err(LinkError::Connect {
                            reason: format!("QEMU exited with {status} before listening ({e})"),
                            log: log_now(&mut child),
                        });
                    }
                    if t0.elapsed() > CONNECT_TIMEOUT {
                        return Err(LinkError::Connect {
                            reason: format!("no listener on {addr} after {CONNECT_TIMEOUT:?}"),
                            log: log_now(&mut child),
                        });
                    }
                    std::thread::sleep(Duration::from_millis(20));
                }
            }
        };
        let _ = stream.set_nodelay(true);
        let mut link = Self {
            child,
            stream,
            elf: elf.to_path_buf(),
            stdout,
            stderr,
            readers,
            decoder: FrameDecoder::new(),
            pending: Vec::new(),
            tx: FrameEncoder::new(),
            hello: HelloInfo {
                version: 0,
                max_payload: 0,
                flags: 0,
                name: String::new(),
            },
            timeout: DEFAULT_TIMEOUT,
        };
        let f = link.recv_timeout(Duration::from_secs(30))?;
        let hello = match (f.kind(), Hello::read(&f.payload)) {
            (Some(MsgType::Hello), Ok(h)) => h,
            _ => return Err(link.protocol(format!("expected Hello, got {f:?}"))),
        };
        link.hello = HelloInfo {
            version: hello.version,
            max_payload: hello.max_payload,
            flags: hello.flags,
            name: String::from_utf8_lossy(hello.name).into_owned(),
        };
        Ok(link)
    }

    /// What the firmware announced at boot.
    pub fn hello(&self) -> &HelloInfo {
        &self.hello
    }

    /// Path of the firmware ELF.
    pub fn elf(&self) -> &Path {
        &self.elf
    }

    /// Counters of the firmware→host direction (the host's decoder).
    pub fn rx_stats(&self) -> &LinkStats {
        self.decoder.stats()
    }

    /// The host's outgoing encoder (e.g. to skip sequence numbers on purpose).
    pub fn encoder(&mut self) -> &mut FrameEncoder {
        &mut self.tx
    }

    /// QEMU's output so far: decoded defmt log, then QEMU's stderr.
    pub fn log(&self) -> String {
        let out = self.stdout.lock().map(|s| s.clone()).unwrap_or_default();
        let err = self.stderr.lock().map(|s| s.clone()).unwrap_or_default();
        let mut s = decode_defmt(&self.elf, &out);
        if !err.is_empty() {
            s.push_str("\n--- qemu stderr ---\n");
            s.push_str(&String::from_utf8_lossy(&err));
        }
        s
    }

    fn protocol(&self, what: String) -> LinkError {
        LinkError::Protocol {
            what,
            log: self.log(),
        }
    }

    fn io(&self, error: std::io::Error) -> LinkError {
        LinkError::Io {
            error,
            log: self.log(),
        }
    }

    /// Sends raw bytes (for fault injection).
    pub fn send_raw(&mut self, bytes: &[u8]) -> Result<(), LinkError> {
        self.stream.write_all(bytes).map_err(|e| self.io(e))
    }

    /// Encodes and sends one frame with the next sequence number; returns the wire bytes.
    pub fn send(&mut self, msg_type: u8, payload: &[u8]) -> Result<Vec<u8>, LinkError> {
        let mut wire = [0u8; MAX_WIRE_LEN];
        let bytes = self.tx.encode(msg_type, payload, &mut wire)?.to_vec();
        self.send_raw(&bytes)?;
        Ok(bytes)
    }

    /// Receives the next valid frame within [`FirmwareLink::timeout`]; rejected chunks are
    /// skipped (and counted in [`FirmwareLink::rx_stats`]).
    pub fn recv(&mut self) -> Result<OwnedFrame, LinkError> {
        self.recv_timeout(self.timeout)
    }

    /// Receives the next valid frame within `timeout`.
    pub fn recv_timeout(&mut self, timeout: Duration) -> Result<OwnedFrame, LinkError> {
        let deadline = Instant::now() + timeout;
        loop {
            // Drain what is buffered first.
            let mut consumed = 0;
            let mut found = None;
            {
                let mut rest: &[u8] = &self.pending;
                while found.is_none() && !rest.is_empty() {
                    let before = rest.len();
                    rest = match self.decoder.feed(rest) {
                        Feed::Consumed => &[],
                        Feed::Frame { frame, remaining } => {
                            found = Some(OwnedFrame {
                                msg_type: frame.msg_type,
                                seq: frame.seq,
                                payload: frame.payload.to_vec(),
                            });
                            remaining
                        }
                        Feed::Error { remaining, .. } => remaining,
                    };
                    consumed += before - rest.len();
                }
            }
            self.pending.drain(..consumed);
            if let Some(f) = found {
                return Ok(f);
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(LinkError::Timeout {
                    what: "a frame".into(),
                    waited: timeout,
                    log: self.log(),
                });
            }
            let _ = self.stream.set_read_timeout(Some(deadline - now));
            let mut buf = [0u8; 4096];
            match self.stream.read(&mut buf) {
                Ok(0) => {
                    return Err(self.io(std::io::Error::new(
                        std::io::ErrorKind::UnexpectedEof,
                        "QEMU closed the serial port",
                    )))
                }
                Ok(n) => self.pending.extend_from_slice(&buf[..n]),
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) => {}
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.io(e)),
            }
        }
    }

    /// Sends a request and returns the next frame, which must be of type `reply`.
    pub fn request(
        &mut self,
        msg_type: MsgType,
        payload: &[u8],
        reply: MsgType,
    ) -> Result<OwnedFrame, LinkError> {
        self.send(msg_type.code(), payload)?;
        let f = self.recv()?;
        if f.kind() != Some(reply) {
            return Err(self.protocol(format!(
                "{msg_type:?} answered by {:?} (type {:#04x}), expected {reply:?}",
                f.kind(),
                f.msg_type
            )));
        }
        Ok(f)
    }

    /// Pings with `payload` and returns the echo.
    pub fn ping(&mut self, payload: &[u8]) -> Result<Vec<u8>, LinkError> {
        Ok(self.request(MsgType::Ping, payload, MsgType::Pong)?.payload)
    }

    /// Asks for the firmware's counters.
    pub fn stats(&mut self) -> Result<StatsReport, LinkError> {
        let f = self.request(MsgType::StatsRequest, &[], MsgType::Stats)?;
        StatsReport::read(&f.payload).map_err(|e| self.protocol(format!("Stats payload: {e}")))
    }

    /// Runs a dummy workload on the firmware and returns its measured cost.
    pub fn cost(&mut self, workload: Workload, iterations: u32) -> Result<CostReport, LinkError> {
        let mut buf = [0u8; MAX_PAYLOAD];
        let mut w = Writer::new(&mut buf);
        CostRequest {
            workload,
            iterations,
        }
        .write(&mut w)
        .map_err(|e| self.protocol(format!("CostRequest: {e}")))?;
        let payload = w.written().to_vec();
        let f = self.request(MsgType::CostRequest, &payload, MsgType::Cost)?;
        CostReport::read(&f.payload).map_err(|e| self.protocol(format!("Cost payload: {e}")))
    }

    /// Waits for QEMU to exit (e.g. after a deliberate fault) and returns its status.
    pub fn wait_exit(&mut self, timeout: Duration) -> Result<ExitStatus, LinkError> {
        let deadline = Instant::now() + timeout;
        loop {
            match self.child.try_wait() {
                Ok(Some(status)) => {
                    // Let the capture threads drain the pipes so `log` is complete.
                    for r in self.readers.drain(..) {
                        let _ = r.join();
                    }
                    return Ok(status);
                }
                Ok(None) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(10))
                }
                Ok(None) => {
                    return Err(LinkError::Timeout {
                        what: "QEMU to exit".into(),
                        waited: timeout,
                        log: self.log(),
                    })
                }
                Err(e) => return Err(self.io(e)),
            }
        }
    }
}

impl Drop for FirmwareLink {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Encodes one frame with an explicit sequence number (for building injected traffic).
pub fn wire_frame(msg_type: u8, seq: u16, payload: &[u8]) -> Result<Vec<u8>, EncodeError> {
    let mut wire = [0u8; MAX_WIRE_LEN];
    let n = encode_frame(msg_type, seq, payload, &mut wire)?;
    Ok(wire[..n].to_vec())
}

/// Boots tried before [`FirmwareLink::boot_with`] gives up.
pub const BOOT_ATTEMPTS: u32 = 4;

/// A loopback port for QEMU's serial server. Ports come from a sequence that starts at an
/// offset derived from the process id, so the tests of one binary, which boot in parallel
/// threads, never pick the same port; a port that is taken is skipped. (Binding port 0 and
/// releasing it lets two threads receive the same port before either QEMU binds it.)
fn pick_port() -> std::io::Result<u16> {
    static NEXT: AtomicU16 = AtomicU16::new(0);
    const FIRST: u32 = 20_000;
    const SPAN: u32 = 40_000;
    let base = std::process::id() % SPAN;
    for _ in 0..500 {
        let offset = u32::from(NEXT.fetch_add(1, Ordering::Relaxed));
        let port = FIRST + (base + offset * 7) % SPAN;
        let Ok(port) = u16::try_from(port) else {
            continue;
        };
        if TcpListener::bind((Ipv4Addr::LOCALHOST, port)).is_ok() {
            return Ok(port);
        }
    }
    TcpListener::bind((Ipv4Addr::LOCALHOST, 0))
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
}

//! `synth record` and `synth monitor`: a running PLC's inputs and outputs over OPC UA, as a
//! CSV log or beside a machine.

use crate::command::live::{monitor, record};
use crate::live::{Connection, Counters, Security, Until};
use crate::pipeline::Error;
use clap::{Args, ValueEnum};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// The server and how to reach it.
#[derive(Debug, Args, Clone)]
pub struct OpcuaArgs {
    /// The PLC's OPC UA server: opc.tcp://HOST:PORT[/PATH].
    #[arg(long, value_name = "URL")]
    pub opcua: String,
    /// Mapping file: one `NODE-ID in|out NAME` per line, e.g. `ns=2;s=button in button`
    /// (`#` comments), as for `synth ingest`.
    #[arg(long, value_name = "FILE")]
    pub map: PathBuf,
    /// Endpoint security: auto takes None when the server offers it, otherwise
    /// Basic256Sha256 (which needs --certs).
    #[arg(long, value_enum, default_value = "auto")]
    pub security: SecurityArg,
    /// Certificate folder for secure endpoints: the client's certificate (own/cert.der,
    /// private/private.pem, made on first use) and the trusted servers' certificates
    /// (trusted/; a refused one lands in rejected/, to move after checking it).
    #[arg(long, value_name = "DIR")]
    pub certs: Option<PathBuf>,
    /// Milliseconds between two samples (one Read of every mapped node each).
    #[arg(long, default_value_t = 50, value_name = "MS", value_parser = clap::value_parser!(u64).range(1..=60_000))]
    pub interval: u64,
}

/// The `--security` values.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum SecurityArg {
    /// None when offered, otherwise Basic256Sha256.
    Auto,
    /// No security.
    None,
    /// Basic256Sha256, signed and encrypted.
    Basic256sha256,
}

impl OpcuaArgs {
    fn connection(&self) -> Connection {
        Connection {
            url: self.opcua.clone(),
            security: match self.security {
                SecurityArg::Auto => Security::Auto,
                SecurityArg::None => Security::None,
                SecurityArg::Basic256sha256 => Security::Basic256Sha256,
            },
            certs: self.certs.clone(),
            interval: Duration::from_millis(self.interval),
        }
    }
}

#[derive(Debug, Args)]
pub struct RecordArgs {
    #[command(flatten)]
    pub opcua: OpcuaArgs,
    /// The CSV log to write (`time,scenario,in:NAME,...,out:NAME,...`; `.gz` compresses),
    /// read by `synth infer --traces`. A reconnect starts a new scenario.
    #[arg(long, value_name = "LOG.csv")]
    pub out: PathBuf,
    /// Stop after this many seconds (default: on SIGINT only).
    #[arg(long, value_name = "SECONDS", conflicts_with = "samples", value_parser = positive_seconds)]
    pub duration: Option<f64>,
    /// Stop after this many rows.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub samples: Option<u64>,
}

#[derive(Debug, Args)]
pub struct MonitorArgs {
    #[command(flatten)]
    pub opcua: OpcuaArgs,
    /// The machine to run beside the PLC (JSON, as `synth infer` writes it).
    #[arg(long, value_name = "M.json")]
    pub ecc: PathBuf,
    /// Stop after this many seconds (default: at the first divergence or on SIGINT).
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    pub duration: Option<f64>,
    /// Output folder: divergences.csv, the samples up to the divergence, for
    /// `synth conform --refine`. Default: `out/monitor`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 => Ok(s),
        _ => Err(format!("{text:?} is not a positive number of seconds")),
    }
}

/// A live counter on stderr: rewritten in place on a terminal, a line a second otherwise.
struct Counter {
    what: &'static str,
    last: Option<Instant>,
    terminal: bool,
    quiet: bool,
}

impl Counter {
    fn new(what: &'static str) -> Counter {
        Counter {
            what,
            last: None,
            terminal: std::io::stderr().is_terminal(),
            quiet: super::quiet(),
        }
    }

    fn show(&mut self, c: &Counters) {
        let every = if self.terminal { 0.2 } else { 1.0 };
        if self.quiet || self.last.is_some_and(|t| t.elapsed().as_secs_f64() < every) {
            return;
        }
        self.last = Some(Instant::now());
        let steps = match self.what {
            "monitoring" => format!(", {} steps agree", c.steps),
            _ => String::new(),
        };
        let text = format!(
            "{}: {} rows{steps}, {} gaps, {:.1} s",
            self.what, c.rows, c.gaps, c.seconds
        );
        use std::io::Write as _;
        let _ = match self.terminal {
            true => write!(std::io::stderr(), "\r{text}\x1b[K"),
            false => writeln!(std::io::stderr(), "{text}"),
        };
    }

    fn end(&self) {
        if self.terminal && !self.quiet && self.last.is_some() {
            super::err_line(format_args!(""));
        }
    }
}

/// `synth record`.
pub fn record_cmd(args: &RecordArgs) -> Result<(), Error> {
    let until = match (args.duration, args.samples) {
        (Some(s), _) => Until::Seconds(s),
        (None, Some(n)) => Until::Samples(n),
        (None, None) => Until::Signal,
    };
    let mut counter = Counter::new("recording");
    let done = record(
        &args.opcua.connection(),
        &args.opcua.map,
        &args.out,
        until,
        &mut |c| counter.show(c),
    );
    counter.end();
    let done = done?;
    out!("{done}");
    super::note_written(std::slice::from_ref(&done.file));
    if done.stopped {
        crate::signals::end_stopped();
    }
    Ok(())
}

/// `synth monitor`.
pub fn monitor_cmd(args: &MonitorArgs) -> Result<(), Error> {
    let until = args.duration.map_or(Until::Signal, Until::Seconds);
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/monitor"));
    let mut counter = Counter::new("monitoring");
    let done = monitor(
        &args.opcua.connection(),
        &args.opcua.map,
        &args.ecc,
        &out,
        until,
        &mut |c| counter.show(c),
    );
    counter.end();
    let done = done?;
    out!("{done}");
    super::show::print_written(&done.files);
    if done.stopped() {
        crate::signals::end_stopped();
    }
    match done.failure() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

//! The operator crate's errors.

use metamoran_bundle::error::InputError;
use metamoran_process::ProcessError;
use std::path::PathBuf;

/// Why an output, a view or a publisher failed. File problems name the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OperatorError {
    /// A bad or unreadable bundle file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A frame could not be processed.
    #[error(transparent)]
    Process(#[from] ProcessError),
    /// An output file could not be written, recorded or drawn.
    #[error("{}: cannot {what} ({reason})", path.display())]
    Output {
        /// The file or folder.
        path: PathBuf,
        /// What was being done ("write", "record", "draw the plot", …).
        what: &'static str,
        /// Why it failed.
        reason: String,
    },
    /// No usable font for the plot labels.
    #[error("{0}")]
    Font(String),
    /// A perimeter file that is unreadable, malformed or out of range.
    #[error("{source_name}: {problem}")]
    Perimeter {
        /// The file (or "built-in perimeter").
        source_name: String,
        /// The field and what is wrong with it.
        problem: String,
    },
    /// The terminal could not be taken over for the live view.
    #[error("cannot start the live view ({0}); run with --no-live")]
    LiveStart(#[source] std::io::Error),
    /// The live view could not be drawn.
    #[error("the live view cannot draw ({0})")]
    LiveDraw(#[source] std::io::Error),
    /// A malformed broker address or sensor id.
    #[error("--mqtt {broker}: {problem}")]
    MqttAddress {
        /// The address given.
        broker: String,
        /// What form is expected.
        problem: String,
    },
    /// The broker refused, did not answer or did not acknowledge.
    #[error("MQTT broker {broker}: {problem}")]
    Broker {
        /// `HOST:PORT`.
        broker: String,
        /// What happened.
        problem: String,
    },
    /// A TLS file or the credentials for the broker are unusable.
    #[error("MQTT TLS/credentials, {what}: {problem}")]
    MqttSecurity {
        /// The file or setting.
        what: String,
        /// What is wrong and what to do.
        problem: String,
    },
    /// A malformed or unreadable site file.
    #[error("{source_name}: {problem}")]
    Site {
        /// The file.
        source_name: String,
        /// The field and what is wrong.
        problem: String,
    },
    /// A malformed NATS URL, site or sensor name.
    #[error("--nats {url}: {problem}")]
    NatsAddress {
        /// The URL given.
        url: String,
        /// What form is expected.
        problem: String,
    },
    /// The NATS server refused, did not answer, or did not store what was sent.
    #[error("NATS server {url}: {problem}")]
    Nats {
        /// The server's URL.
        url: String,
        /// What happened and what to do.
        problem: String,
    },
    /// A message could not be queued for publishing.
    #[error("MQTT {topic}: {reason}")]
    Publish {
        /// The topic.
        topic: String,
        /// Why.
        reason: String,
    },
}

impl OperatorError {
    /// A failure to `what` the file at `path`.
    pub fn output(path: &std::path::Path, what: &'static str, reason: impl ToString) -> Self {
        Self::Output {
            path: path.to_owned(),
            what,
            reason: reason.to_string(),
        }
    }
}

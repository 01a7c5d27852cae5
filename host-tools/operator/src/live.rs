//! The operator's live terminal view (ratatui): the confirmed tracks with class, depth,
//! azimuth, speed and zones, the latest alerts, and the telemetry link's health, redrawn as each frame's
//! results arrive from the module.
//!
//! [`draw`] is a pure function of [`OperatorState`], so tests render it into ratatui's
//! `TestBackend`; [`LiveView`] puts it on the terminal (alternate screen) while a run lasts.

use crate::OperatorError;
use crate::geofence::Alert;
use ratatui::layout::{Constraint, Layout};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Cell, Paragraph, Row, Table};
use serde::Serialize;
use std::time::Duration;

/// One confirmed track as the operator sees it, and as a sensor publishes it to the site.
#[derive(Clone, Debug, Serialize, serde::Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TrackRow {
    /// Track id.
    pub id: u32,
    /// Class (the track's vote).
    pub class: String,
    /// Range, m.
    pub depth_m: f64,
    /// Azimuth, degrees.
    pub azimuth_deg: f64,
    /// Ground speed, m/s.
    pub speed_mps: f64,
    /// Ground position in the sensor's frame `[x, z]`, m.
    pub position_m: [f64; 2],
    /// Ground velocity in the sensor's frame, m/s.
    pub velocity_mps: [f64; 2],
    /// Whether this frame gave it no detection (its position is a prediction).
    pub coasting: bool,
    /// The camera instance of this frame's detection, when there was one (it names the
    /// object in the sensor's results and inspection plots).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instance: Option<u16>,
    /// Zones it is in.
    pub zones: Vec<String>,
}

impl TrackRow {
    /// The row of `track`, in `zones`.
    pub fn of(track: &crate::tracking::Track, zones: Vec<String>) -> Self {
        Self {
            id: track.id,
            class: track.class.clone(),
            depth_m: track.range_m(),
            azimuth_deg: track.azimuth_deg(),
            speed_mps: track.velocity_mps[0].hypot(track.velocity_mps[1]),
            position_m: track.position_m,
            velocity_mps: track.velocity_mps,
            coasting: track.detection.is_none(),
            instance: None,
            zones,
        }
    }
}

/// How many of the latest alerts the view lists.
pub const ALERT_LINES: usize = 8;

/// The telemetry link as the host sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LinkHealth {
    /// Whether there is a link at all (the module under QEMU; in process there is none).
    pub present: bool,
    /// Messages accepted from the module.
    pub accepted: u32,
    /// Messages lost (counter gaps not filled in).
    pub lost: u32,
    /// Authentication failures: messages whose tag did not verify.
    pub auth_failures: u32,
    /// Replayed or stale messages refused.
    pub replayed: u32,
    /// Undecodable messages.
    pub malformed: u32,
    /// The last frame's latency, ms.
    pub latency_ms: f64,
    /// Mean latency over the frames so far, ms.
    pub mean_latency_ms: f64,
}

impl LinkHealth {
    /// Folds in frame number `seen` (1-based count) with its `latency` and the link counters.
    pub fn update(
        &mut self,
        seen: u32,
        latency: Duration,
        link: Option<metamoran_dsp::wire::LinkStats>,
    ) {
        let ms = latency.as_secs_f64() * 1e3;
        self.latency_ms = ms;
        self.mean_latency_ms += (ms - self.mean_latency_ms) / f64::from(seen.max(1));
        if let Some(l) = link {
            self.present = true;
            self.accepted = l.accepted;
            self.lost = l.lost;
            self.auth_failures = l.bad_tag;
            self.replayed = l.replayed;
            self.malformed = l.malformed + l.bad_version + l.overflow;
        }
    }

    /// Loss as a fraction of the messages that should have arrived.
    pub fn loss(&self) -> f64 {
        let expected = self.accepted + self.lost;
        if expected == 0 {
            0.0
        } else {
            f64::from(self.lost) / f64::from(expected)
        }
    }
}

/// Everything the view shows.
#[derive(Clone, Debug, Default)]
pub struct OperatorState {
    /// First line: what is running.
    pub title: String,
    /// Where the module runs, in words.
    pub edge: String,
    /// Frames received so far.
    pub frames_seen: u32,
    /// Frames in the run.
    pub frames: u32,
    /// Time of the latest frame, s.
    pub time_s: f64,
    /// The confirmed tracks after the latest frame.
    pub tracks: Vec<TrackRow>,
    /// Every alert so far, in order (the view lists the latest [`ALERT_LINES`]).
    pub alerts: Vec<Alert>,
    /// Link health.
    pub link: LinkHealth,
}

/// Draws the operator view into `frame`: the title, the objects, the latest alerts and the
/// link's health, top to bottom.
pub fn draw(frame: &mut ratatui::Frame<'_>, s: &OperatorState) {
    let [head, objects, alerts, link] = Layout::vertical([
        Constraint::Length(2),
        Constraint::Min(4),
        Constraint::Length(ALERT_LINES as u16 + 2),
        Constraint::Length(3),
    ])
    .areas(frame.area());
    let bold = Style::new().add_modifier(Modifier::BOLD);
    frame.render_widget(
        Paragraph::new(vec![
            Line::from(Span::styled(s.title.as_str(), bold)),
            Line::from(format!(
                "frame {}/{}  t = {:.1} s  module {}",
                s.frames_seen, s.frames, s.time_s, s.edge
            )),
        ]),
        head,
    );
    frame.render_widget(objects_table(&s.tracks, bold), objects);
    frame.render_widget(alert_list(&s.alerts), alerts);
    frame.render_widget(
        Paragraph::new(link_line(&s.link)).block(Block::bordered().title(" link ")),
        link,
    );
}

/// The tracks, one row each; rows of tracks inside a zone in red.
fn objects_table(tracks: &[TrackRow], bold: Style) -> Table<'_> {
    let header = Row::new(["id", "class", "depth m", "az °", "m/s", "zones"]).style(bold);
    let rows = tracks.iter().map(|t| {
        let zones = if t.zones.is_empty() {
            "—".to_owned()
        } else {
            t.zones.join(", ")
        };
        let style = if t.zones.is_empty() {
            Style::new()
        } else {
            Style::new().fg(Color::Red)
        };
        Row::new([
            Cell::from(t.id.to_string()),
            Cell::from(t.class.as_str()),
            Cell::from(format!(
                "{:.2}{}",
                t.depth_m,
                if t.coasting { "?" } else { "" }
            )),
            Cell::from(format!("{:.1}", t.azimuth_deg)),
            Cell::from(format!("{:.1}", t.speed_mps)),
            Cell::from(zones),
        ])
        .style(style)
    });
    let widths = [
        Constraint::Length(4),
        Constraint::Length(8),
        Constraint::Length(9),
        Constraint::Length(7),
        Constraint::Length(8),
        Constraint::Min(10),
    ];
    Table::new(rows, widths)
        .header(header)
        .block(Block::bordered().title(" tracks (? = coasting) "))
}

/// The latest [`ALERT_LINES`] alerts, oldest first.
fn alert_list(alerts: &[Alert]) -> Paragraph<'static> {
    let first = alerts.len().saturating_sub(ALERT_LINES);
    let lines: Vec<Line<'_>> = if alerts.is_empty() {
        vec![Line::from("none")]
    } else {
        alerts[first..]
            .iter()
            .map(|a| {
                Line::from(format!(
                    "t={:>5.1} s  {:<8} {} #{} {} at {:.2} m, {:+.1}°",
                    a.time_s,
                    format!("{:?}", a.kind).to_lowercase(),
                    a.class,
                    a.track,
                    a.zone,
                    a.depth_m,
                    a.azimuth_deg
                ))
            })
            .collect()
    };
    let title = format!(" alerts ({}) ", alerts.len());
    Paragraph::new(lines).block(Block::bordered().title(title))
}

/// The link's counters and latency in one line.
fn link_line(l: &LinkHealth) -> String {
    if l.present {
        format!(
            "accepted {}  lost {} ({:.1} %)  auth failures {}  replays {}  malformed {}  latency {:.0} ms (mean {:.0} ms)",
            l.accepted,
            l.lost,
            100.0 * l.loss(),
            l.auth_failures,
            l.replayed,
            l.malformed,
            l.latency_ms,
            l.mean_latency_ms
        )
    } else {
        format!(
            "no link: the module runs in this process  latency {:.0} ms (mean {:.0} ms)",
            l.latency_ms, l.mean_latency_ms
        )
    }
}

/// The view on this process's terminal (alternate screen) while it lives.
pub struct LiveView {
    terminal: ratatui::DefaultTerminal,
}

impl LiveView {
    /// Takes over the terminal.
    ///
    /// # Errors
    /// [`OperatorError`] if the terminal cannot be set up (run without the live view: `--no-live`).
    pub fn start() -> Result<Self, OperatorError> {
        ratatui::try_init()
            .map(|terminal| Self { terminal })
            .map_err(OperatorError::LiveStart)
    }

    /// Redraws the view.
    ///
    /// # Errors
    /// [`OperatorError`] if the terminal cannot be written.
    pub fn show(&mut self, s: &OperatorState) -> Result<(), OperatorError> {
        self.terminal
            .draw(|f| draw(f, s))
            .map(|_| ())
            .map_err(OperatorError::LiveDraw)
    }
}

impl Drop for LiveView {
    fn drop(&mut self) {
        ratatui::restore();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geofence::AlertKind;
    use ratatui::{Terminal, backend::TestBackend};

    fn screen(s: &OperatorState) -> String {
        let mut t = Terminal::new(TestBackend::new(110, 24)).unwrap();
        t.draw(|f| draw(f, s)).unwrap();
        let buf = t.backend().buffer().clone();
        (0..buf.area.height)
            .map(|y| {
                (0..buf.area.width)
                    .map(|x| buf[(x, y)].symbol().to_owned())
                    .collect::<String>()
                    + "\n"
            })
            .collect()
    }

    fn alert(i: u32) -> Alert {
        Alert {
            kind: if i.is_multiple_of(2) {
                AlertKind::Enter
            } else {
                AlertKind::Exit
            },
            zone: "gate".into(),
            track: 2,
            instance: Some(5),
            class: "person".into(),
            depth_m: 12.0 + f64::from(i),
            azimuth_deg: -10.0,
            position_m: [-2.0, 12.0],
            velocity_mps: [1.0, 0.0],
            closing_mps: None,
            inside_s: None,
            frame: i,
            time_s: f64::from(i) / 2.0,
        }
    }

    #[test]
    fn the_view_shows_objects_latest_alerts_and_link_health() {
        let mut link = LinkHealth::default();
        let stats = metamoran_dsp::wire::LinkStats {
            accepted: 95,
            lost: 5,
            bad_tag: 3,
            replayed: 1,
            ..Default::default()
        };
        link.update(1, Duration::from_millis(120), Some(stats));
        link.update(2, Duration::from_millis(80), Some(stats));
        assert!((link.mean_latency_ms - 100.0).abs() < 1e-9);
        let s = OperatorState {
            title: "metamoran demo".into(),
            edge: "firmware under QEMU".into(),
            frames_seen: 2,
            frames: 22,
            time_s: 0.5,
            tracks: vec![
                TrackRow {
                    id: 1,
                    class: "car".into(),
                    depth_m: 37.126,
                    azimuth_deg: 3.04,
                    speed_mps: 0.04,
                    position_m: [1.97, 37.07],
                    velocity_mps: [0.04, 0.0],
                    coasting: false,
                    instance: Some(1),
                    zones: vec!["far lot".into()],
                },
                TrackRow {
                    id: 2,
                    class: "person".into(),
                    depth_m: 12.5,
                    azimuth_deg: -8.0,
                    speed_mps: 1.4,
                    position_m: [-1.74, 12.38],
                    velocity_mps: [1.4, 0.0],
                    coasting: true,
                    instance: None,
                    zones: vec![],
                },
            ],
            alerts: (0..11).map(alert).collect(),
            link,
        };
        let text = screen(&s);
        assert!(text.contains("frame 2/22"), "{text}");
        assert!(text.contains("37.13") && text.contains("3.0") && text.contains("far lot"));
        assert!(text.contains("person") && text.contains("12.50?") && text.contains("1.4"));
        // The latest ALERT_LINES alerts: 3..=10, not 0..=2.
        assert!(text.contains("alerts (11)"));
        assert!(
            text.contains("22.00 m") && text.contains("15.00 m"),
            "{text}"
        );
        assert!(!text.contains("14.00 m"), "{text}");
        assert!(text.contains("lost 5 (5.0 %)") && text.contains("auth failures 3"));
        assert!(text.contains("latency 80 ms (mean 100 ms)"), "{text}");

        let none = OperatorState::default();
        let text = screen(&none);
        assert!(text.contains("no link") && text.contains("none"), "{text}");
    }
}

//! `bump [FILES]` without a subcommand: the docking window, and the session
//! options around it: joysticks (`--two-boxes`, `--joystick-map`,
//! `--rotation`), recording (`--record`) and replay (`--play`, in the window
//! or `--headless`), with the timing report printed on exit.
//!
//! Without `--record` or `--play`, files are read on another thread while the
//! window is already up. A recording or a replay needs the whole scene from
//! the first frame, so the files are read before the window opens; a replay
//! takes its files and options from the log unless the command line names
//! them.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use bump::collide::{ColliderKind, Method};
use bump::input::{JoystickMap, RotationMapping};
use bump::model::{LoadOptions, Molecule, RadiiSet, builtin};
use bump::session::{Session, SessionLog, Settings, replay};
use clap::Args;

/// Options of the docking window.
#[derive(Debug, Args, Clone, Default)]
pub struct WindowArgs {
    /// With one complex file: the drug residue: RESNAME, RESNAME:CHAIN:SEQ or
    /// auto (SEQ may end in an insertion code, as in 52A).
    #[arg(long)]
    ligand: Option<String>,
    /// Collider: brute, grid or hashed (default hashed, or the log's).
    #[arg(long)]
    collider: Option<String>,
    /// Move-to-touch method: swept (default) or thesis (end-pose pair list
    /// and bisection, for comparison).
    #[arg(long)]
    method: Option<String>,
    /// Radius table: bondi (default) or thesis.
    #[arg(long)]
    radii: Option<String>,
    /// Two joystick boxes: the first moves the view, the second the
    /// selected molecule (the thesis's -J).
    #[arg(short = 'J', long)]
    two_boxes: bool,
    /// Joystick map file (TOML); default: assets/joystick-map.toml, built in.
    #[arg(long, value_name = "FILE")]
    joystick_map: Option<PathBuf>,
    /// Rotation mapping: users (twist turns about the vertical) or thesis
    /// (the original); overrides the map file.
    #[arg(long)]
    rotation: Option<String>,
    /// No rumble on contact.
    #[arg(long)]
    no_rumble: bool,
    /// Record every frame's input to FILE (the thesis's -l).
    #[arg(long, value_name = "FILE", conflicts_with = "play")]
    record: Option<PathBuf>,
    /// Replay a recorded session instead of live input, then exit (the
    /// thesis's -p).
    #[arg(long, value_name = "FILE")]
    play: Option<PathBuf>,
    /// With --play: no window; replay as fast as possible and print the
    /// timing report and final poses.
    #[arg(long, requires = "play")]
    headless: bool,
}

/// The scene a session runs on, as recorded in a log's `meta` lines.
#[derive(Debug, Clone, Default)]
struct SceneSpec {
    files: Vec<PathBuf>,
    ligand: Option<String>,
    radii: RadiiSet,
    collider: ColliderKind,
    method: Method,
}

impl SceneSpec {
    /// From the command line, falling back on a log's meta values.
    fn resolve(
        files: &[PathBuf],
        a: &WindowArgs,
        log: Option<(&SessionLog, &Path)>,
    ) -> anyhow::Result<Self> {
        let meta = |k: &str| log.and_then(|(l, _)| l.meta_value(k).map(str::to_string));
        let pick = |cli: &Option<String>, key: &str| cli.clone().or_else(|| meta(key));
        let radii = pick(&a.radii, "radii").unwrap_or_else(|| "bondi".into());
        let collider = pick(&a.collider, "collider").unwrap_or_else(|| "hashed".into());
        let method = pick(&a.method, "method").unwrap_or_else(|| "swept".into());
        let mut spec = Self {
            files: files.to_vec(),
            ligand: a.ligand.clone(),
            radii: RadiiSet::parse(&radii)
                .with_context(|| format!("unknown radii `{radii}` (bondi or thesis)"))?,
            collider: ColliderKind::parse(&collider).with_context(|| {
                format!("unknown collider `{collider}` (brute, grid or hashed)")
            })?,
            method: Method::parse(&method)
                .with_context(|| format!("unknown method `{method}` (swept or thesis)"))?,
        };
        if let Some((log, log_path)) = log
            && spec.files.is_empty()
        {
            spec.ligand = spec.ligand.or_else(|| meta("ligand"));
            for f in log.meta_values("file") {
                spec.files.push(locate(f, log_path));
            }
        }
        Ok(spec)
    }

    // Only a recording, which needs the window, writes these.
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    fn meta(&self, two_boxes: bool, molecules: &[Molecule]) -> Vec<(String, String)> {
        let mut m = vec![(
            "bump-version".to_string(),
            env!("CARGO_PKG_VERSION").to_string(),
        )];
        for f in &self.files {
            m.push(("file".into(), f.display().to_string()));
        }
        if let Some(l) = &self.ligand {
            m.push(("ligand".into(), l.clone()));
        }
        m.push(("radii".into(), self.radii.name().into()));
        m.push(("collider".into(), self.collider.name().into()));
        m.push(("method".into(), self.method.name().into()));
        m.push(("two-boxes".into(), two_boxes.to_string()));
        m.push(("atoms".into(), atom_counts(molecules)));
        m
    }

    fn settings(&self) -> Settings {
        let mut s = Settings {
            collider: self.collider,
            ..Settings::default()
        };
        s.touch.method = self.method;
        s
    }

    fn label(&self) -> String {
        format!(
            "collider {}, method {}",
            self.collider.name(),
            self.method.name()
        )
    }

    /// Reads every file now (record and replay need the whole scene at once).
    fn load_all(&self) -> anyhow::Result<Vec<Molecule>> {
        if self.files.is_empty() {
            let (r, d) = builtin::scene(self.radii);
            return Ok(vec![r, d]);
        }
        let opts = LoadOptions {
            radii: self.radii,
            ..LoadOptions::default()
        };
        let single = self.files.len() == 1;
        let mut out = Vec::new();
        for (k, f) in self.files.iter().enumerate() {
            let split = k == 0 && (single || self.ligand.is_some());
            let (molecules, warnings) = load_for_window(f, split, self.ligand.as_deref(), &opts)
                .map_err(|e| anyhow::anyhow!(e))?;
            for w in warnings {
                eprintln!("bump: warning: {w}");
            }
            out.extend(molecules);
        }
        Ok(out)
    }
}

/// A log's file path as recorded, or else relative to the log's folder.
fn locate(recorded: &str, log_path: &Path) -> PathBuf {
    let p = PathBuf::from(recorded);
    if p.exists() || p.is_absolute() {
        return p;
    }
    let beside = log_path.parent().map(|d| d.join(&p));
    match beside {
        Some(b) if b.exists() => b,
        _ => p,
    }
}

fn atom_counts(molecules: &[Molecule]) -> String {
    molecules
        .iter()
        .map(|m| m.len().to_string())
        .collect::<Vec<_>>()
        .join(",")
}

fn joystick_map(a: &WindowArgs) -> anyhow::Result<JoystickMap> {
    let mut map = match &a.joystick_map {
        Some(p) => JoystickMap::read(p)?,
        None => JoystickMap::default(),
    };
    if let Some(r) = &a.rotation {
        map.rotation = RotationMapping::parse(r)
            .with_context(|| format!("unknown rotation mapping `{r}` (users or thesis)"))?;
    }
    Ok(map)
}

/// Runs the window (or a headless replay).
pub fn run(files: &[PathBuf], a: &WindowArgs) -> anyhow::Result<()> {
    let map = joystick_map(a)?;
    let log = match &a.play {
        Some(p) => Some(SessionLog::read(p)?),
        None => None,
    };
    let spec = SceneSpec::resolve(files, a, log.as_ref().zip(a.play.as_deref()))?;
    let two_boxes = a.two_boxes
        || log
            .as_ref()
            .and_then(|l| l.meta_value("two-boxes"))
            .is_some_and(|v| v == "true");
    let played = match (&log, &a.play) {
        (Some(log), Some(path)) => {
            let molecules = spec.load_all()?;
            if let Some(recorded) = log.meta_value("atoms")
                && recorded != atom_counts(&molecules)
            {
                bail!(
                    "{}: recorded on molecules of {recorded} atoms, but these have {}: not the same scene",
                    path.display(),
                    atom_counts(&molecules)
                );
            }
            let mut session = Session::new(molecules, spec.settings())?;
            if a.headless {
                return headless(&mut session, log, path, &spec);
            }
            Some((session, log, path.as_path()))
        }
        _ => None,
    };
    #[cfg(feature = "app")]
    {
        shell::run(a, &spec, map, two_boxes, played)
    }
    #[cfg(not(feature = "app"))]
    {
        let _ = (map, two_boxes, played);
        bail!(
            "this bump was built without its window (cargo feature `app`): use `--play LOG --headless` or the commands (bump --help)"
        )
    }
}

fn headless(
    session: &mut Session,
    log: &SessionLog,
    path: &Path,
    spec: &SceneSpec,
) -> anyhow::Result<()> {
    let mut new_contacts = 0usize;
    let done = replay::replay(session, log, |_, out| {
        new_contacts += usize::from(out.new_contact);
    });
    outln!(
        "replayed {} of {} frames ({:.2} s of recorded time) from {}",
        done.frames,
        log.frames.len(),
        log.duration(),
        path.display()
    );
    outln!("{}", done.timing.report(&spec.label()));
    outln!(
        "contact events (beeps): {new_contacts}; contacts at the end: {}",
        session.contacts().len()
    );
    for (k, b) in session.bodies().iter().enumerate() {
        let (t, q) = (b.pose.translation, b.pose.rotation);
        outln!(
            "final pose {k} ({}): centre {:.6} {:.6} {:.6} Å, rotation xyzw {:.9} {:.9} {:.9} {:.9}",
            b.molecule.name,
            t.x,
            t.y,
            t.z,
            q.x,
            q.y,
            q.z,
            q.w
        );
    }
    match replay::mismatched_finals(session, log) {
        None => outln!("the log holds no final poses to compare with"),
        Some(m) if m.is_empty() => {
            outln!("final poses match the recording bit for bit");
        }
        Some(m) => outln!(
            "final poses differ from the recording for molecule(s) {m:?} (another collider, method or build?)"
        ),
    }
    Ok(())
}

/// Reads one file for the window: a complex split into receptor and drug
/// (`split`), or the whole file as one molecule. When the split fails the
/// whole file is kept and the reason returned as a warning.
fn load_for_window(
    f: &Path,
    split: bool,
    ligand: Option<&str>,
    opts: &LoadOptions,
) -> Result<(Vec<Molecule>, Vec<String>), String> {
    use bump::model::{self, LigandSpec};
    let loaded = model::load(f, opts).map_err(|e| e.to_string())?;
    let mut warnings = loaded.warnings.clone();
    if split {
        let text = ligand.unwrap_or("auto");
        let parts = LigandSpec::parse(text)
            .map_err(|e| format!("--ligand {text}: {e}"))
            .and_then(|spec| {
                model::split_complex(&loaded.structure, &spec).map_err(|e| e.to_string())
            });
        match parts {
            Ok((r, d)) => return Ok((vec![r, d], warnings)),
            Err(e) => warnings.push(e),
        }
    }
    let m = model::receptor_only(&loaded.structure).map_err(|e| e.to_string())?;
    Ok((vec![m], warnings))
}

/// The window itself (feature `app`).
#[cfg(feature = "app")]
mod shell {
    use super::*;
    use bump::app::LoadEvent;
    use bump::session::LogWriter;

    /// Opens the window: replaying `played`, recording, on the built-in
    /// scene, or on files read on another thread while the window is up.
    pub fn run(
        a: &WindowArgs,
        spec: &SceneSpec,
        map: JoystickMap,
        two_boxes: bool,
        played: Option<(Session, &SessionLog, &Path)>,
    ) -> anyhow::Result<()> {
        if let Some((session, log, path)) = played {
            let options = bump::app::Options {
                joystick_map: map,
                two_boxes,
                rumble: false,
                record: None,
                play: Some(log.clone()),
            };
            let ended = bump::app::run(session, Vec::new(), None, options)?;
            report_window(&ended, spec, Some((log, path)));
            return Ok(());
        }
        let options = |record| bump::app::Options {
            joystick_map: map.clone(),
            two_boxes,
            rumble: !a.no_rumble,
            record,
            play: None,
        };
        if let Some(path) = &a.record {
            let molecules = spec.load_all()?;
            let writer = LogWriter::create(path, &spec.meta(two_boxes, &molecules))?;
            let session = Session::new(molecules, spec.settings())?;
            let msg = format!("recording to {}", path.display());
            let ended = bump::app::run(session, vec![msg], None, options(Some(writer)))?;
            report_window(&ended, spec, None);
            return Ok(());
        }
        if spec.files.is_empty() {
            let molecules = spec.load_all()?;
            let session = Session::new(molecules, spec.settings())?;
            let ended = bump::app::run(session, Vec::new(), None, options(None))?;
            report_window(&ended, spec, None);
            return Ok(());
        }
        let rx = spawn_loader(spec);
        let ended = bump::app::run(
            Session::empty(spec.settings()),
            Vec::new(),
            Some(rx),
            options(None),
        )?;
        report_window(&ended, spec, None);
        Ok(())
    }

    fn report_window(
        ended: &bump::app::Ended,
        spec: &SceneSpec,
        played: Option<(&SessionLog, &Path)>,
    ) {
        if let Some(p) = &ended.recorded {
            eprintln!("bump: recorded the session to {}", p.display());
        }
        if let (Some((log, path)), Some(n)) = (played, ended.replayed) {
            outln!(
                "replayed {n} of {} frames from {}",
                log.frames.len(),
                path.display()
            );
            if let Some(s) = &ended.session {
                match replay::mismatched_finals(s, log) {
                    Some(m) if m.is_empty() => {
                        outln!("final poses match the recording bit for bit")
                    }
                    Some(m) => {
                        outln!("final poses differ from the recording for molecule(s) {m:?}")
                    }
                    None => {}
                }
            }
        }
        outln!("{}", ended.timing.report(&spec.label()));
    }

    fn spawn_loader(spec: &SceneSpec) -> std::sync::mpsc::Receiver<LoadEvent> {
        let opts = LoadOptions {
            radii: spec.radii,
            ..LoadOptions::default()
        };
        let files = spec.files.clone();
        let ligand = spec.ligand.clone();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let single = files.len() == 1;
            for (k, f) in files.iter().enumerate() {
                let label = f.display().to_string();
                if tx.send(LoadEvent::Reading(label.clone())).is_err() {
                    return; // the window is gone
                }
                let t0 = std::time::Instant::now();
                let split = k == 0 && (single || ligand.is_some());
                let event = match load_for_window(f, split, ligand.as_deref(), &opts) {
                    Ok((molecules, warnings)) => LoadEvent::Loaded {
                        label,
                        molecules,
                        warnings,
                        seconds: t0.elapsed().as_secs_f64(),
                    },
                    Err(e) => LoadEvent::Failed(e),
                };
                // A failure is said once, by the window's status line
                // (which also prints it on stderr).
                if tx.send(event).is_err() {
                    return;
                }
            }
        });
        rx
    }
}

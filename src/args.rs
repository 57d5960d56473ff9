//! Command-line arguments (clap derive).

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};

use crate::render::{Color, Format};

/// cellc: describe a robot manipulation cell, check it, compile it, plan in it.
#[derive(Parser, Debug)]
#[command(name = "cellc", version, about, propagate_version = true)]
pub struct Args {
    /// Colour in human output: `auto` colours when standard error is a terminal and
    /// `NO_COLOR` is unset or empty (https://no-color.org; `CLICOLOR_FORCE=1` forces it).
    #[arg(long, global = true, value_enum, default_value = "auto")]
    pub color: ColorChoice,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// When to colour human output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColorChoice {
    /// When standard error is a terminal, unless `NO_COLOR` says otherwise.
    Auto,
    /// Always, whatever `NO_COLOR` and the terminal say.
    Always,
    /// Never.
    Never,
}

impl ColorChoice {
    /// Whether diagnostics on standard error are coloured: the one place the process
    /// decides it, once, in [`crate::dispatch`]. `auto` follows anstream (the crate clap
    /// colours its own help with), so `NO_COLOR`, `CLICOLOR`, `CLICOLOR_FORCE` and
    /// `TERM=dumb` mean for cellc what they mean for clap and cargo; an explicit choice
    /// wins over all of them, as no-color.org asks.
    pub fn decide(self) -> Color {
        match self {
            ColorChoice::Always => Color::Always,
            ColorChoice::Never => Color::Never,
            ColorChoice::Auto => match anstream::AutoStream::choice(&std::io::stderr()) {
                anstream::ColorChoice::Never => Color::Never,
                _ => Color::Always,
            },
        }
    }
}

/// Artifact encodings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ArtifactEncoding {
    /// JSON (readable, the default).
    Json,
    /// Compact binary.
    Bin,
}

/// Where ROS packages are looked for, shared by every command that reads cells.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct PackageArgs {
    /// A folder of ROS packages (holding `NAME/package.xml`) or a package itself, searched
    /// for `package://NAME/...` files after the cell's `package` items and before the
    /// folders of `ROS_PACKAGE_PATH`. Repeatable; searched in the order given.
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
}

/// What to plan, shared by `cellc plan` and `cellc run`.
#[derive(clap::Args, Debug, Clone)]
pub struct RequestArgs {
    /// A `.cell` file (compiled and verified now) or an artifact.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,
    /// Where ROS packages are.
    #[command(flatten)]
    pub packages: PackageArgs,
    /// A request declared in the cell (default: the first one).
    #[arg(long)]
    pub request: Option<String>,
    /// The object to move, for a request given here.
    #[arg(long, requires_all = ["from", "to"], conflicts_with = "request")]
    pub object: Option<String>,
    /// Where the object is: `HOLDER[.GRASP] in WS` or `HOLDER at (x, y, z) [rpy (r, p, y)]`
    /// (metres and degrees unless written).
    #[arg(long, requires_all = ["object", "to"])]
    pub from: Option<String>,
    /// Where it must go, in the same form.
    #[arg(long, requires_all = ["object", "from"])]
    pub to: Option<String>,
    /// Seed of the randomized solvers.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Plan the high level only (no joint motions).
    #[arg(long)]
    pub no_motions: bool,
    /// Arc weights for this request instead of the cell's: `MOVE,TRANSITION` (e.g. `1,2`,
    /// the original planner's costs).
    #[arg(long, value_parser = parse_weights)]
    pub weights: Option<(f64, f64)>,
    /// Give up when planning takes longer than this many milliseconds.
    #[arg(long)]
    pub time_budget: Option<u64>,
    /// The share of every joint's velocity limit the motions use, above 0 and at most 1
    /// (MoveIt's `max_velocity_scaling_factor`); out of range is R0012.
    #[arg(
        long,
        value_name = "F",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    pub velocity_scaling: f64,
    /// The share of every joint's acceleration (and jerk) limit the motions use, above 0
    /// and at most 1; out of range is R0012.
    #[arg(
        long,
        value_name = "F",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    pub acceleration_scaling: f64,
    /// Trajectory points every 1/HZ seconds, the last at the motion's end, as a controller
    /// running at HZ (at most 1000) takes them, instead of the time parameterisation's
    /// knots; out of range is R0012.
    #[arg(long, value_name = "HZ", allow_negative_numbers = true)]
    pub rate: Option<f64>,
    /// A task the cell declares: its moves one after the other, in the world.
    #[arg(long, conflicts_with_all = ["request", "object", "moves"])]
    pub task: Option<String>,
    /// A move of a task given here, `OBJECT to PLACEMENT` (e.g. `ball to bin in
    /// ws_right_bin`); repeat it for several moves, carried out in the order given.
    #[arg(long = "move", value_name = "MOVE", conflicts_with_all = ["request", "object"])]
    pub moves: Vec<String>,
    /// Start from this world document (docs/world.md): a task's or moves' world instead
    /// of the cell's `world`; for a request, the other objects and the arms (the
    /// request's object is put at its start).
    #[arg(long)]
    pub world: Option<PathBuf>,
    /// Start from the world a state file of `cellc serve` holds, as from `--world FILE`
    /// (docs/world.md); refused while that world is uncertain. The file is only read:
    /// `cellc run` does not write its result back (the service owns the file; a run is a
    /// simulation from its world), and a running service may keep writing it meanwhile.
    #[arg(long, value_name = "PATH", conflicts_with = "world")]
    pub state: Option<PathBuf>,
    /// When other objects are in a move's way (one stands at its goal, or they block
    /// every way there), move them to free resting poses first; the output shows those
    /// moves, then the move itself.
    #[arg(long)]
    pub clear: bool,
    /// Output style: `human` numbered steps (diagnostics on standard error), `short` one
    /// line per plan, step and diagnostic, `json` one document (docs/world.md,
    /// "Machine-readable results").
    #[arg(long, value_enum, default_value = "human")]
    pub format: Format,
}

fn parse_weights(text: &str) -> Result<(f64, f64), String> {
    let (a, b) = text
        .split_once(',')
        .ok_or("write `MOVE,TRANSITION`, e.g. `1,2`")?;
    let parse = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|w| w.is_finite() && *w >= 0.0)
            .ok_or_else(|| format!("`{s}` is not a weight (a number of zero or more)"))
    };
    Ok((parse(a)?, parse(b)?))
}

/// Flags shared by the commands that report diagnostics.
#[derive(clap::Args, Debug, Clone)]
pub struct ReportFlags {
    /// Output style for diagnostics: `human` snippets on standard error, `short` one line
    /// each or `json` one document (docs/diagnostics/README.md), on standard output.
    #[arg(long, value_enum, default_value = "human")]
    pub format: Format,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Check cells and report every problem (exit 1 on errors).
    Check {
        /// Cell files.
        #[arg(required = true, value_name = "INPUT")]
        files: Vec<PathBuf>,
        /// Treat warnings as errors.
        #[arg(long)]
        deny_warnings: bool,
        /// Output flags.
        #[command(flatten)]
        report: ReportFlags,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
    /// Format cell files in the canonical layout.
    Fmt {
        /// Cell files.
        #[arg(required = true, value_name = "INPUT")]
        files: Vec<PathBuf>,
        /// Do not write; exit 1 if any file is not formatted.
        #[arg(long)]
        check: bool,
    },
    /// Compile a cell into an artifact (the object-state graphs and the resolved cell).
    Build {
        /// The cell.
        #[arg(value_name = "INPUT")]
        cell: PathBuf,
        /// Output file (default: the cell's path with `.artifact.json` or `.artifact.bin`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Artifact encoding.
        #[arg(long, value_enum, default_value = "json")]
        encoding: ArtifactEncoding,
        /// Output flags.
        #[command(flatten)]
        report: ReportFlags,
        /// Also print the workspaces, their boxes and who reaches them (human output only:
        /// with `--format short` or `json`, standard output is the diagnostics').
        #[arg(long)]
        explain: bool,
        /// Skip the kinematic check of every arc (done by default when the cell has arms).
        #[arg(long)]
        no_verify: bool,
        /// Seed of the randomized solvers used to verify arcs.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Treat warnings as errors.
        #[arg(long)]
        deny_warnings: bool,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
    /// Summarise a cell or an artifact: workspaces, end-effectors, graph sizes per object.
    Info {
        /// A `.cell` file or an artifact.
        #[arg(value_name = "INPUT")]
        file: PathBuf,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
    /// Print the object-state graph of one object.
    Graph {
        /// A `.cell` file or an artifact.
        #[arg(value_name = "INPUT")]
        file: PathBuf,
        /// The object.
        #[arg(long)]
        object: String,
        /// What to write: the graph as DOT, JSON or SVG (in every command `--format` is
        /// how diagnostics are written, so the graph's form has a flag of its own).
        #[arg(long, value_enum, default_value = "dot")]
        emit: GraphFormat,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
    /// Write one self-contained HTML page showing the cell in 3D (robots, surfaces,
    /// objects, workspaces and reach boxes), its object-state graphs and, with a request,
    /// a task or a plan file, the plan animated on a timeline (docs/view.md).
    View {
        /// A `.cell` file (compiled and verified now) or an artifact.
        #[arg(value_name = "INPUT")]
        input: PathBuf,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
        /// A request declared in the cell: planned now and animated.
        #[arg(long, conflicts_with_all = ["task", "plan"])]
        request: Option<String>,
        /// The object to move, for a request given here.
        #[arg(long, requires_all = ["from", "to"], conflicts_with_all = ["request", "task", "plan"])]
        object: Option<String>,
        /// Where the object is (as `cellc plan --from`).
        #[arg(long, requires_all = ["object", "to"])]
        from: Option<String>,
        /// Where it must go (as `cellc plan --to`).
        #[arg(long, requires_all = ["object", "from"])]
        to: Option<String>,
        /// A task the cell declares: planned now and animated move after move.
        #[arg(long, conflicts_with = "plan")]
        task: Option<String>,
        /// A plan document written by `cellc plan CELL --format json`, animated instead of
        /// planning.
        #[arg(long, value_name = "PLAN.json")]
        plan: Option<PathBuf>,
        /// Start from this world document (docs/world.md).
        #[arg(long)]
        world: Option<PathBuf>,
        /// Start from the world a state file of `cellc serve` holds (only read; refused
        /// while that world is uncertain).
        #[arg(long, value_name = "PATH", conflicts_with = "world")]
        state: Option<PathBuf>,
        /// Seed of the randomized solvers.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The page to write.
        #[arg(short = 'o', long = "output", value_name = "VIEW.html")]
        output: PathBuf,
    },
    /// Plan a move request: a named request of the cell (the first one by default), or one
    /// given with --object, --from and --to (`HOLDER[.GRASP] in WS` or `HOLDER at (x, y, z)
    /// [rpy (r, p, y)]`, metres and degrees unless written).
    Plan {
        /// The request.
        #[command(flatten)]
        request: RequestArgs,
        /// Write this instead of the plans on standard output: `follow-joint-trajectory`,
        /// each plan's motions as `control_msgs/action/FollowJointTrajectory` goals, one
        /// per arm per step (JSON, docs/world.md). Diagnostics go to standard error, so
        /// only with `--format human`; nothing is written when a move has no plan.
        #[arg(long, value_enum, value_name = "WHAT", conflicts_with = "no_motions")]
        emit: Option<PlanEmit>,
    },
    /// Plan a request as `cellc plan` does, then execute it in the kinematic simulator and
    /// report the object's final pose and its error.
    Run {
        /// The request.
        #[command(flatten)]
        request: RequestArgs,
        /// Make the motion of step N (1-based) of the first plan executed fail in the
        /// simulator, to see recovery; N is from 1 to that plan's number of steps
        /// (anything else is refused, E0509).
        #[arg(long, value_name = "N")]
        fail_at: Option<usize>,
    },
    /// Serve the cell over HTTP (JSON, docs/service.md): load and verify it once, then
    /// plan, execute and explain requests against a world it keeps.
    Serve {
        /// A `.cell` file (compiled and verified now) or an artifact.
        #[arg(value_name = "INPUT")]
        input: PathBuf,
        /// Where to listen (loopback unless told otherwise; port 0 picks a free one).
        #[arg(long, default_value = "127.0.0.1:7878")]
        addr: std::net::SocketAddr,
        /// Seed of verification and of plans that give none.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// The state file keeping the world and the execution journal (SQLite), created
        /// when absent [default: INPUT's name with `.state.sqlite`, next to it].
        #[arg(long, value_name = "PATH", conflicts_with = "ephemeral")]
        state: Option<PathBuf>,
        /// Keep the world in memory only: nothing survives a stop (tests, benchmarks).
        #[arg(long)]
        ephemeral: bool,
        /// How far an acknowledged write survives: `full` a power loss, `normal` a crash
        /// of the process (SQLite's `synchronous`).
        #[arg(long, value_enum, default_value_t = DurabilityArg::Full)]
        durability: DurabilityArg,
        /// Ended executions the journal keeps (the newest).
        #[arg(long, value_name = "N", default_value_t = 10_000)]
        journal_keep: u32,
        /// Days the journal keeps ended executions.
        #[arg(long, value_name = "DAYS", default_value_t = 30)]
        journal_days: u32,
        /// Execute in the simulator at a robot's pace times F: each step takes its
        /// trajectory's time (a hand 0.3 s) times F before it is done; 0, the default,
        /// at once. For trying clients' timeouts and recovery against real timing.
        #[arg(long, value_name = "F", default_value_t = 0.0, value_parser = pace)]
        sim_pace: f64,
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
    /// Explain a diagnostic code, e.g. `cellc explain E0101`.
    Explain {
        /// The code.
        code: String,
    },
    /// Export the object-state graphs to another tool's format.
    Export {
        /// The format.
        #[command(subcommand)]
        format: ExportFormat,
    },
    /// Import another system's description of a cell as a cell file.
    Import {
        /// What to import.
        #[command(subcommand)]
        source: ImportSource,
    },
    /// Serve the Language Server Protocol on standard input and output, for editors
    /// (diagnostics as you type, hover, go to definition, completion, formatting).
    Lsp {
        /// Where ROS packages are.
        #[command(flatten)]
        packages: PackageArgs,
    },
}

/// `--sim-pace`: a finite factor from 0 to 10.
fn pace(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(f) if (0.0..=10.0).contains(&f) => Ok(f),
        _ => Err("a factor from 0 to 10".to_string()),
    }
}

/// `cellc serve --durability`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum DurabilityArg {
    /// Every commit waits for the disk: a power loss loses nothing acknowledged.
    Full,
    /// A crash of the process loses nothing; a power loss may lose the last writes.
    Normal,
}

/// What `cellc import` reads.
#[derive(Subcommand, Debug)]
pub enum ImportSource {
    /// The SQLite grasp database of the dual_manipulation planner (Marino et al.), as an
    /// abstract-form cell; run `cellc check` on the output to see its warnings.
    Dualmanip {
        /// The database file.
        #[arg(value_name = "INPUT")]
        db: PathBuf,
        /// The cell file to write (written only when the import succeeds).
        #[arg(short, long)]
        output: PathBuf,
        /// Output flags.
        #[command(flatten)]
        report: ReportFlags,
    },
}

/// What `cellc export` writes.
#[derive(Subcommand, Debug)]
pub enum ExportFormat {
    /// A PDDL domain per object (the arcs the planner searches as actions, their weights
    /// x 1000 as action costs) and a problem per request the cell declares, for planners
    /// such as Fast Downward (docs/pddl.md).
    Pddl(PddlArgs),
}

/// What `cellc export pddl` exports.
#[derive(clap::Args, Debug, Clone)]
pub struct PddlArgs {
    /// A `.cell` file (compiled and verified now) or an artifact.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,
    /// Only this object: its domain and a problem per request of it.
    #[arg(long)]
    pub object: Option<String>,
    /// Only this request the cell declares: its object's domain and its problem.
    #[arg(long, conflicts_with = "object")]
    pub request: Option<String>,
    /// Where the object is, for one problem given here (with --object and --to), as in
    /// `cellc plan`: `HOLDER[.GRASP] in WS` or `HOLDER at (x, y, z) [rpy (r, p, y)]`.
    #[arg(long, requires_all = ["object", "to"])]
    pub from: Option<String>,
    /// Where it must go, in the same form.
    #[arg(long, requires_all = ["object", "from"])]
    pub to: Option<String>,
    /// The folder to write (made when missing): `DIR/OBJECT/domain.pddl` and
    /// `DIR/OBJECT/PROBLEM.pddl`, named as in PDDL.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Seed of the randomized solvers (verifying a cell, placing a start in a hand).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Where ROS packages are.
    #[command(flatten)]
    pub packages: PackageArgs,
}

/// What `cellc plan --emit` writes instead of the plans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlanEmit {
    /// Each plan's motions as `control_msgs/action/FollowJointTrajectory` goals (JSON).
    FollowJointTrajectory,
}

/// Output of `cellc graph`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GraphFormat {
    /// Graphviz DOT: a cluster per workspace, solid transitions, dashed moves.
    Dot,
    /// JSON with names.
    Json,
    /// SVG laid out by cellc (no Graphviz needed): a column per workspace, a row per
    /// end-effector, pruned arcs grey with their reasons as tooltips.
    Svg,
}

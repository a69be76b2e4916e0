//! ROS 2 command-line arguments, as `ros2 run` and launch files pass them: `--ros-args -r FROM:=TO
//! -r __ns:=/NS -r __node:=NAME -p NAME:=VALUE --params-file FILE --log-level [LOGGER:=]LEVEL ...`.
//!
//! - The `--ros-args` sections are split and parsed by the `ros2args` crate (the ROS 2 command-line
//!   design: several sections, `--` ends one, node-specific `NODE:FROM:=TO` and `NODE:NAME:=VALUE`).
//! - Parameter files are read here in rcl's layout (`/ns/node:` or nested `ns: node:` keys, `/**`
//!   and `*` wildcards, nested parameter maps named with `.`), matched against the node's fully
//!   qualified name as rclcpp does; files apply in order, then `-p`, later ones winning.
//! - Every setting of a node is a ROS parameter of the same name: a flag's long name in snake_case
//!   (`--max-program-hours` is `max_program_hours`), a positional by its name (`program`). A
//!   parameter becomes its flag before clap parses, so one parser checks both; the flags stay as
//!   aliases, and a flag and a parameter that disagree are an error. `--namespace`, `--node-name`
//!   and `--remap` are the ROS names `__ns`, `__node` and `-r`, not parameters.
//! - Fail closed: an unknown parameter addressed to this node (`-p`, or a file key naming it without
//!   a wildcard) is an error; one under a wildcard key (meant for every node of a launch) is skipped
//!   with a warning. `--log-config-file` is refused: not supported. `--enclave` names the DDS
//!   Security enclave ([`crate::security`]).

use clap::{ArgAction, ArgMatches, Command, Parser};
use clap::parser::ValueSource;
use ros2_client::{Parameter, ParameterValue};
use std::any::TypeId;
use std::path::Path;
use yaml_rust2::Yaml;

/// Clap ids of the node-identity flags, which are ROS names rather than parameters.
const NAME_IDS: [&str; 3] = ["namespace", "node_name", "remaps"];

/// Largest parameter file read, bytes (a params file is a few kB).
const MAX_PARAMS_FILE: u64 = 1 << 20;

/// What the ROS arguments ask of a node beyond its own settings.
#[derive(Debug, Clone)]
pub struct RosOptions {
    /// Every setting as a declared parameter, with the value the node runs with.
    pub parameters: Vec<Parameter>,
    /// Publish log records on /rosout (`--enable-rosout-logs`, the default, or `--disable-rosout-logs`).
    pub rosout: bool,
    /// Log to stderr (`--disable-stdout-logs` turns it off).
    pub stdout_logs: bool,
    /// Tracing directives from `--log-level` (`LEVEL` for the node, `LOGGER:=LEVEL` for a target).
    pub log_filter: Option<String>,
    /// What was skipped (parameters under wildcard keys that are not this node's), for the log once
    /// it is set up.
    pub warnings: Vec<String>,
    /// The DDS Security enclave (`--enclave /NAME`), used when `ROS_SECURITY_ENABLE=true` ([`crate::security`]).
    pub enclave: Option<String>,
}

impl Default for RosOptions {
    /// As without `--ros-args`: no parameters declared, logs on /rosout and stderr.
    fn default() -> Self {
        RosOptions { parameters: Vec::new(), rosout: true, stdout_logs: true, log_filter: None, warnings: Vec::new(), enclave: None }
    }
}

/// Why the ROS arguments were refused.
#[derive(Debug)]
pub enum RosArgsError {
    /// The node's own flags (after the parameters became flags): clap's usage error, help or version.
    Clap(clap::Error),
    /// A ROS argument, parameter or parameter file that cannot be used.
    Ros(String),
}

impl std::fmt::Display for RosArgsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RosArgsError::Clap(e) => write!(f, "{e}"),
            RosArgsError::Ros(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for RosArgsError {}

fn ros_err(s: impl Into<String>) -> RosArgsError {
    RosArgsError::Ros(s.into())
}

/// The ROS type of a setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Bool,
    Integer,
    Double,
    Text,
    TextArray,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Bool => "bool",
            Kind::Integer => "integer",
            Kind::Double => "double",
            Kind::Text => "string",
            Kind::TextArray => "string_array",
        }
    }
}

/// A node setting that is also a ROS parameter.
#[derive(Debug, Clone)]
struct Setting {
    /// Parameter name (snake_case).
    name: String,
    /// Clap id.
    id: String,
    /// `--long` of a flag; None for a positional.
    long: Option<String>,
    kind: Kind,
    /// A switch (`--fast`), given without a value: the value it sets (true for SetTrue, false for
    /// SetFalse).
    switch: Option<bool>,
    default: Option<String>,
}

impl Setting {
    /// How the command line names it: `--long`, or `<ID>` for a positional.
    fn flag(&self) -> String {
        self.long.as_ref().map_or_else(|| format!("<{}>", self.id.to_uppercase()), |l| format!("--{l}"))
    }
}

/// The settings of `cmd` (its own arguments, not its subcommands').
fn settings(cmd: &Command) -> Vec<Setting> {
    let mut out = Vec::new();
    for a in cmd.get_arguments() {
        let id = a.get_id().as_str().to_string();
        if matches!(a.get_action(), ArgAction::Help | ArgAction::HelpShort | ArgAction::HelpLong | ArgAction::Version) || NAME_IDS.contains(&id.as_str()) {
            continue;
        }
        let long = a.get_long().map(str::to_string);
        let name = long.as_deref().map_or_else(|| id.clone(), |l| l.replace('-', "_"));
        let t = a.get_value_parser().type_id();
        let kind = match a.get_action() {
            ArgAction::SetTrue | ArgAction::SetFalse => Kind::Bool,
            ArgAction::Append => Kind::TextArray,
            _ if t == TypeId::of::<f64>() || t == TypeId::of::<f32>() => Kind::Double,
            _ if [TypeId::of::<u64>(), TypeId::of::<i64>(), TypeId::of::<usize>(), TypeId::of::<u32>(), TypeId::of::<i32>(), TypeId::of::<u16>(), TypeId::of::<u8>()].iter().any(|x| t == *x) => Kind::Integer,
            _ if t == TypeId::of::<bool>() => Kind::Bool,
            _ => Kind::Text,
        };
        let default = a.get_default_values().first().map(|v| v.to_string_lossy().into_owned());
        let switch = match a.get_action() {
            ArgAction::SetTrue => Some(true),
            ArgAction::SetFalse => Some(false),
            _ => None,
        };
        out.push(Setting { name, id, long, kind, switch, default });
    }
    out
}

/// The `--help` text listing a command's parameters.
fn parameter_help(settings: &[Setting]) -> String {
    let mut s = String::from("ROS 2 parameters (--ros-args -p NAME:=VALUE, --params-file FILE; read at start, read-only):\n");
    for p in settings {
        let default = match (&p.default, p.kind) {
            (Some(d), _) => format!(", default {d}"),
            (None, Kind::Bool) => ", default false".into(),
            (None, Kind::TextArray) => ", default []".into(),
            (None, _) => ", not set by default".into(),
        };
        s.push_str(&format!("  {:<28} {}{default} ({})\n", p.name, p.kind.name(), p.flag()));
    }
    s.push_str("ROS names: -r __ns:=/NS (--namespace), -r __node:=NAME (--node-name), -r FROM:=TO (--remap).");
    s
}

/// A parameter value as the flag's values, checked against the setting's type.
fn values_of(p: &Setting, v: &Yaml, source: &str) -> Result<Vec<String>, RosArgsError> {
    let bad = |what: &str| ros_err(format!("parameter {} ({source}): expected {what}, got {v:?}", p.name));
    let scalar = |v: &Yaml| -> Option<String> {
        match v {
            Yaml::String(s) | Yaml::Real(s) => Some(s.clone()),
            Yaml::Integer(i) => Some(i.to_string()),
            Yaml::Boolean(b) => Some(b.to_string()),
            _ => None,
        }
    };
    Ok(match p.kind {
        Kind::Bool => match v {
            Yaml::Boolean(b) => vec![b.to_string()],
            _ => return Err(bad("true or false")),
        },
        Kind::Integer => match v {
            Yaml::Integer(i) => vec![i.to_string()],
            _ => return Err(bad("an integer")),
        },
        Kind::Double => match v {
            Yaml::Real(s) => vec![s.clone()],
            Yaml::Integer(i) => vec![i.to_string()],
            _ => return Err(bad("a number")),
        },
        Kind::Text => vec![scalar(v).ok_or_else(|| bad("a string"))?],
        Kind::TextArray => match v {
            Yaml::Array(items) => items.iter().map(|x| scalar(x).ok_or_else(|| bad("a list of strings"))).collect::<Result<_, _>>()?,
            other => vec![scalar(other).ok_or_else(|| bad("a list of strings"))?],
        },
    })
}

/// One parameter assignment and where it came from; `strict`: addressed to this node by name.
#[derive(Debug, Clone)]
struct Assignment {
    name: String,
    value: Yaml,
    source: String,
    strict: bool,
}

/// Whether a parameter-file key (node path) selects the node `fqn`, as rclcpp matches them: a key
/// without a leading `/` is taken from the root; `**` is any number of name tokens, `*` one.
fn key_matches(key: &str, fqn: &str) -> bool {
    let key = if key.starts_with('/') { key.to_string() } else { format!("/{key}") };
    if key.contains('*') {
        ros2args::match_wildcard_pattern(&key, fqn)
    } else {
        key == fqn
    }
}

/// The parameters of `path` for the node `fqn`, in file order.
fn read_params_file(path: &Path, fqn: &str) -> Result<Vec<Assignment>, RosArgsError> {
    let shown = path.display();
    let size = std::fs::metadata(path).map_err(|e| ros_err(format!("--params-file {shown}: {e}")))?.len();
    if size > MAX_PARAMS_FILE {
        return Err(ros_err(format!("--params-file {shown}: {size} bytes, more than the {MAX_PARAMS_FILE} a parameter file may have")));
    }
    let text = std::fs::read_to_string(path).map_err(|e| ros_err(format!("--params-file {shown}: {e}")))?;
    let docs = yaml_rust2::YamlLoader::load_from_str(&text).map_err(|e| ros_err(format!("--params-file {shown}: {e}")))?;
    let mut out = Vec::new();
    for doc in &docs {
        walk_nodes(doc, "", path, fqn, &mut out)?;
    }
    Ok(out)
}

/// Descend node keys until `ros__parameters`.
fn walk_nodes(y: &Yaml, prefix: &str, path: &Path, fqn: &str, out: &mut Vec<Assignment>) -> Result<(), RosArgsError> {
    let map = match y {
        Yaml::Hash(h) => h,
        Yaml::Null => return Ok(()),
        _ => return Err(ros_err(format!("--params-file {}: under '{}' expected node names or ros__parameters, got {y:?}", path.display(), if prefix.is_empty() { "/" } else { prefix }))),
    };
    for (k, v) in map {
        let key = match k {
            Yaml::String(s) => s.as_str(),
            _ => return Err(ros_err(format!("--params-file {}: a key under '{prefix}' is not a name: {k:?}", path.display()))),
        };
        if key == "ros__parameters" {
            if prefix.is_empty() {
                return Err(ros_err(format!("--params-file {}: ros__parameters must be under a node name", path.display())));
            }
            if key_matches(prefix, fqn) {
                let strict = !prefix.contains('*');
                let source = format!("{} under {prefix}", path.display());
                walk_params(v, "", &source, strict, out)?;
            }
        } else {
            let p = if prefix.is_empty() { key.to_string() } else { format!("{}/{}", prefix.trim_end_matches('/'), key.trim_start_matches('/')) };
            walk_nodes(v, &p, path, fqn, out)?;
        }
    }
    Ok(())
}

/// Parameters under `ros__parameters`, nested maps named with `.`.
fn walk_params(y: &Yaml, prefix: &str, source: &str, strict: bool, out: &mut Vec<Assignment>) -> Result<(), RosArgsError> {
    let map = match y {
        Yaml::Hash(h) => h,
        Yaml::Null => return Ok(()),
        _ => return Err(ros_err(format!("{source}: ros__parameters{} must be a map of names to values", if prefix.is_empty() { String::new() } else { format!(".{prefix}") }))),
    };
    for (k, v) in map {
        let key = match k {
            Yaml::String(s) => s.clone(),
            _ => return Err(ros_err(format!("{source}: a parameter name is not a string: {k:?}"))),
        };
        let name = if prefix.is_empty() { key } else { format!("{prefix}.{key}") };
        match v {
            Yaml::Hash(_) => walk_params(v, &name, source, strict, out)?,
            _ => out.push(Assignment { name, value: v.clone(), source: source.to_string(), strict }),
        }
    }
    Ok(())
}

/// The `--log-level` rules as tracing directives: a level alone or for the node's own logger sets the
/// default; another logger's name is a tracing target (`rustdds:=debug`).
fn log_filter(levels: &[ros2args::LogLevelAssignment], node: &str, fqn: &str) -> Option<String> {
    if levels.is_empty() {
        return None;
    }
    let level = |l: ros2args::LogLevel| match l {
        ros2args::LogLevel::Debug => "debug",
        ros2args::LogLevel::Info => "info",
        ros2args::LogLevel::Warn => "warn",
        ros2args::LogLevel::Error | ros2args::LogLevel::Fatal => "error",
    };
    let dotted = fqn.trim_start_matches('/').replace('/', ".");
    let mut default = "info";
    let mut targets = Vec::new();
    for a in levels {
        match &a.logger_name {
            None => default = level(a.level),
            Some(n) if n == node || *n == dotted || n == fqn => default = level(a.level),
            Some(n) => targets.push(format!("{n}={}", level(a.level))),
        }
    }
    let mut f = default.to_string();
    for t in targets {
        f.push(',');
        f.push_str(&t);
    }
    Some(crate::user_log_filter(&f))
}

/// The value `id` has in `m` on the command line, as strings (None: not given there).
fn given(m: &ArgMatches, s: &Setting) -> Option<Vec<String>> {
    if m.value_source(&s.id) != Some(ValueSource::CommandLine) {
        return None;
    }
    if s.kind == Kind::Bool {
        return Some(vec![m.try_get_one::<bool>(&s.id).ok().flatten().copied().unwrap_or(false).to_string()]);
    }
    m.get_raw(&s.id).map(|v| v.map(|x| x.to_string_lossy().into_owned()).collect())
}

/// A declared parameter's value from the parsed settings.
fn declared(m: &ArgMatches, s: &Setting) -> ParameterValue {
    if s.kind == Kind::Bool {
        return ParameterValue::Boolean(m.try_get_one::<bool>(&s.id).ok().flatten().copied().unwrap_or(false));
    }
    let raw: Vec<String> = match m.get_raw(&s.id) {
        Some(v) => v.map(|x| x.to_string_lossy().into_owned()).collect(),
        None => return if s.kind == Kind::TextArray { ParameterValue::StringArray(Vec::new()) } else { ParameterValue::NotSet },
    };
    match s.kind {
        Kind::TextArray => ParameterValue::StringArray(raw),
        _ => {
            let one = raw.into_iter().next().unwrap_or_default();
            match s.kind {
                Kind::Double => one.parse().map_or(ParameterValue::String(one), ParameterValue::Double),
                Kind::Integer => one.parse().map_or(ParameterValue::String(one), ParameterValue::Integer),
                _ => ParameterValue::String(one),
            }
        }
    }
}

/// Parse a node's command line (`argv[0]` first): its own flags and the ROS arguments. `default_node`
/// is the node's name unless `-r __node:=` or `--node-name` says otherwise.
pub fn parse_from<A: Parser>(default_node: &str, argv: Vec<String>) -> Result<(A, RosOptions), RosArgsError> {
    let (ros, user) = ros2args::parse_ros2_args(&argv).map_err(|e| ros_err(format!("--ros-args: {e}")))?;
    if let Some(f) = &ros.log_config_file {
        return Err(ros_err(format!("--ros-args --log-config-file {}: not supported (use --log-level or RUST_LOG)", f.display())));
    }
    let base = A::command();
    // The command whose settings the parameters are: the subcommand named on the command line, if any.
    let sub = if base.has_subcommands() {
        user.iter().skip(1).find(|t| base.find_subcommand(t.as_str()).is_some()).cloned()
    } else {
        None
    };
    let target = match &sub {
        Some(name) => base.find_subcommand(name).cloned(),
        None if base.has_subcommands() => None,
        None => Some(base.clone()),
    };
    let list = target.as_ref().map(settings).unwrap_or_default();
    // What the command line itself gives (lenient: a positional may still come from a parameter).
    let lenient = base.clone().ignore_errors(true).try_get_matches_from(&user).ok();
    let given_m: Option<&ArgMatches> = match (&lenient, &sub) {
        (Some(m), Some(s)) => m.subcommand_matches(s),
        (Some(m), None) => Some(m),
        _ => None,
    };
    // (clap panics in debug builds when asked for an id the command does not have.)
    let known = |id: &str| target.as_ref().is_some_and(|c| c.get_arguments().any(|a| a.get_id() == id));
    let flag_of = |id: &str| -> Option<String> {
        given_m.filter(|m| known(id) && m.value_source(id) == Some(ValueSource::CommandLine)).and_then(|m| m.get_raw(id)).and_then(|mut v| v.next()).map(|x| x.to_string_lossy().into_owned())
    };
    let has_names = known("namespace");

    let mut flags: Vec<String> = Vec::new();
    let mut positionals: Vec<String> = Vec::new();
    // Node identity: the first __node / __ns rule that applies wins (rcl), a flag must agree.
    let flag_node = flag_of("node_name");
    let node_rule = |from: &str, node: &str| ros.remap_rules.iter().find(|r| (r.from == from || (from == "__node" && r.from == "__name")) && r.applies_to_node(node)).map(|r| r.to.clone());
    let pre_node = flag_node.clone().unwrap_or_else(|| default_node.to_string());
    let ros_node = node_rule("__node", &pre_node);
    let node = match (&ros_node, &flag_node) {
        (Some(r), Some(f)) if r != f => return Err(ros_err(format!("the node name is '{r}' by -r __node:= and '{f}' by --node-name: give one"))),
        (Some(r), _) => {
            if flag_node.is_none() {
                flags.extend(["--node-name".to_string(), r.clone()]);
            }
            r.clone()
        }
        (None, _) => pre_node.clone(),
    };
    let flag_ns = flag_of("namespace");
    let ros_ns = node_rule("__ns", &node).or_else(|| node_rule("__ns", &pre_node));
    let namespace = match (&ros_ns, &flag_ns) {
        (Some(r), Some(f)) if r.trim_end_matches('/') != f.trim_end_matches('/') => return Err(ros_err(format!("the namespace is '{r}' by -r __ns:= and '{f}' by --namespace: give one"))),
        (Some(r), _) => {
            if !r.starts_with('/') {
                return Err(ros_err(format!("-r __ns:={r}: a namespace must be absolute (start with /)")));
            }
            if flag_ns.is_none() {
                flags.extend(["--namespace".to_string(), r.clone()]);
            }
            r.clone()
        }
        (None, Some(f)) => f.clone(),
        (None, None) => target.as_ref().and_then(|c| c.get_arguments().find(|a| a.get_id() == "namespace")).and_then(|a| a.get_default_values().first().map(|v| v.to_string_lossy().into_owned())).unwrap_or_else(|| "/".into()),
    };
    if (ros_node.is_some() || ros_ns.is_some()) && !has_names {
        return Err(ros_err("-r __node:= / __ns:= given to a command that opens no ROS node"));
    }
    let fqn = format!("{}/{}", namespace.trim_end_matches('/'), node);
    for r in ros.remap_rules.iter().filter(|r| !matches!(r.from.as_str(), "__node" | "__name" | "__ns")) {
        if r.node_name.as_deref().is_some_and(|n| n != node && n != fqn) {
            continue;
        }
        if !has_names {
            return Err(ros_err(format!("-r {}:={}: this command has no topics to remap", r.from, r.to)));
        }
        flags.extend(["--remap".to_string(), format!("{}:={}", r.from, r.to)]);
    }

    // Parameters: files in order, then -p; a later assignment of a name replaces an earlier one.
    let mut assigned: Vec<Assignment> = Vec::new();
    for f in &ros.param_files {
        assigned.extend(read_params_file(f, &fqn)?);
    }
    for p in &ros.param_assignments {
        if p.node_name.as_deref().is_some_and(|n| n != node && n != fqn && !key_matches(n, &fqn)) {
            continue;
        }
        assigned.push(Assignment { name: p.name.clone(), value: p.value.clone(), source: format!("-p {}:=...", p.name), strict: true });
    }
    let mut warnings = Vec::new();
    let mut last: Vec<Assignment> = Vec::new();
    for a in assigned {
        last.retain(|b| b.name != a.name);
        last.push(a);
    }
    for a in &last {
        let Some(s) = list.iter().find(|s| s.name == a.name) else {
            if a.strict {
                let known: Vec<&str> = list.iter().map(|s| s.name.as_str()).collect();
                return Err(ros_err(format!("parameter {} ({}): not a parameter of {fqn} (its parameters: {})", a.name, a.source, known.join(", "))));
            }
            warnings.push(format!("parameter {} ({}): not a parameter of {fqn}, skipped", a.name, a.source));
            continue;
        };
        let vals = values_of(s, &a.value, &a.source)?;
        if let Some(g) = given_m.and_then(|m| given(m, s)) {
            if g != vals {
                return Err(ros_err(format!("{} is {} on the command line but parameter {} is {} ({}): give one", s.flag(), g.join(" "), s.name, vals.join(" "), a.source)));
            }
            continue;
        }
        match (&s.long, s.kind) {
            (Some(l), Kind::Bool) if s.switch.is_some() => {
                if Some(vals[0] == "true") == s.switch {
                    flags.push(format!("--{l}"));
                }
            }
            (Some(l), _) => {
                for v in vals {
                    flags.push(format!("--{l}={v}"));
                }
            }
            (None, _) => positionals.extend(vals),
        }
    }

    // The final command line: the node's own tokens, the parameters as flags, positionals after `--`.
    let split = user.iter().position(|t| t == "--").unwrap_or(user.len());
    let mut line: Vec<String> = user[..split].to_vec();
    line.extend(flags);
    if split < user.len() || !positionals.is_empty() {
        line.push("--".into());
    }
    line.extend(user[split.saturating_add(1).min(user.len())..].iter().cloned());
    line.extend(positionals);
    let mut cmd = base;
    if cmd.has_subcommands() {
        let names: Vec<String> = cmd.get_subcommands().map(|c| c.get_name().to_string()).collect();
        for n in names {
            cmd = cmd.mut_subcommand(n, |c| {
                let help = parameter_help(&settings(&c));
                c.after_long_help(help)
            });
        }
    } else {
        let help = parameter_help(&list);
        cmd = cmd.after_long_help(help);
    }
    let m = cmd.try_get_matches_from(&line).map_err(RosArgsError::Clap)?;
    let args = A::from_arg_matches(&m).map_err(RosArgsError::Clap)?;
    let tm = match &sub {
        Some(s) => m.subcommand_matches(s),
        None if target.is_some() => Some(&m),
        None => None,
    };
    let parameters = match tm {
        Some(tm) => list.iter().map(|s| Parameter { name: s.name.clone(), value: declared(tm, s) }).collect(),
        None => Vec::new(),
    };
    let log_filter = log_filter(&ros.log_levels, &node, &fqn);
    Ok((args, RosOptions { parameters, rosout: ros.logging_output.rosout.unwrap_or(true), stdout_logs: ros.logging_output.stdout.unwrap_or(true), log_filter, warnings, enclave: ros.enclave.clone() }))
}

/// [`parse_from`] on this process's arguments: prints clap's help or error, or the ROS argument's
/// error, and exits (0 for help and version, 2 for bad input) when it cannot go on.
pub fn parse<A: Parser>(default_node: &str) -> (A, RosOptions) {
    match parse_from(default_node, std::env::args().collect()) {
        Ok(x) => x,
        Err(RosArgsError::Clap(e)) => e.exit(),
        Err(RosArgsError::Ros(s)) => {
            eprintln!("error: {s}");
            std::process::exit(crate::EXIT_INPUT);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node's settings as the nodes declare them.
    #[derive(Parser, Debug)]
    #[command(name = "t")]
    struct T {
        program: String,
        #[arg(long, default_value_t = 1000.0)]
        rate: f64,
        #[arg(long)]
        fast: bool,
        #[arg(long = "max-program-hours", default_value_t = 24.0)]
        max_program_hours: f64,
        #[arg(long = "flush-ms", default_value_t = 200)]
        flush_ms: u64,
        #[arg(long = "topic")]
        topics: Vec<String>,
        #[arg(long = "feed")]
        feed_mm_per_min: Option<f64>,
        #[command(flatten)]
        common: crate::CommonArgs,
    }

    fn argv(s: &str) -> Vec<String> {
        std::iter::once("t".to_string()).chain(s.split_whitespace().map(str::to_string)).collect()
    }

    fn parse(s: &str) -> Result<(T, RosOptions), RosArgsError> {
        parse_from::<T>("dflt", argv(s))
    }

    fn value(o: &RosOptions, name: &str) -> ParameterValue {
        o.parameters.iter().find(|p| p.name == name).map(|p| p.value.clone()).unwrap_or_else(|| panic!("{name} not declared"))
    }

    fn file(text: &str) -> tempfile::NamedTempFile {
        let mut f = tempfile::NamedTempFile::new().expect("temp file");
        std::io::Write::write_all(&mut f, text.as_bytes()).expect("write");
        f
    }

    #[test]
    fn own_flags_alone_parse_as_before_and_every_setting_is_declared() {
        let (t, o) = parse("p.ngc --rate 500 --fast --namespace /x").unwrap();
        assert_eq!((t.program.as_str(), t.rate, t.fast, t.common.namespace.as_str()), ("p.ngc", 500.0, true, "/x"));
        assert_eq!(value(&o, "rate"), ParameterValue::Double(500.0));
        assert_eq!(value(&o, "fast"), ParameterValue::Boolean(true));
        assert_eq!(value(&o, "program"), ParameterValue::String("p.ngc".into()));
        assert_eq!(value(&o, "max_program_hours"), ParameterValue::Double(24.0));
        assert_eq!(value(&o, "flush_ms"), ParameterValue::Integer(200));
        assert_eq!(value(&o, "topic"), ParameterValue::StringArray(vec![]));
        assert_eq!(value(&o, "feed"), ParameterValue::NotSet, "an unset option is declared not set");
        assert!(o.parameters.iter().all(|p| !["namespace", "node_name", "remap"].contains(&p.name.as_str())), "ROS names are not parameters");
        assert!(o.rosout && o.stdout_logs && o.log_filter.is_none());
        assert_eq!(value(&o, "use_sim_time"), ParameterValue::Boolean(false), "ROS 2's default: wall time");
        let (t, o) = parse("p.ngc --ros-args -p use_sim_time:=true").unwrap();
        assert!(t.common.use_sim_time);
        assert_eq!(value(&o, "use_sim_time"), ParameterValue::Boolean(true));
    }

    #[test]
    fn names_remaps_and_parameters_from_the_command_line() {
        let (t, o) = parse("--ros-args -r __ns:=/cell1 -r __node:=m1 -r commanded/axis_state:=/cnc/state -r other:a:=b -p program:=p.ngc -p rate:=250 -p fast:=true -p max_program_hours:=2 -p topic:=[a,b] --log-level debug").unwrap();
        assert_eq!((t.common.namespace.as_str(), t.common.node_name.as_deref()), ("/cell1", Some("m1")));
        assert_eq!(t.common.remaps, vec![("commanded/axis_state".to_string(), "/cnc/state".to_string())], "a rule for another node does not apply");
        assert_eq!((t.program.as_str(), t.rate, t.fast, t.max_program_hours), ("p.ngc", 250.0, true, 2.0));
        assert_eq!(t.topics, ["a", "b"]);
        assert_eq!(value(&o, "rate"), ParameterValue::Double(250.0));
        assert!(o.log_filter.as_deref().is_some_and(|f| f.starts_with("debug,")));
        // The first __ns rule wins (rcl), node-specific ones apply to this node's name.
        let (t, _) = parse("p --ros-args -r __ns:=/a -r __ns:=/b -r dflt:__node:=n2").unwrap();
        assert_eq!((t.common.namespace.as_str(), t.common.node_name.as_deref()), ("/a", Some("n2")));
    }

    #[test]
    fn parameter_files_match_the_node_as_rclcpp_does() {
        let f = file("/**:\n  ros__parameters:\n    rate: 100.0\n    unknown_to_us: 3\n/cell1/m1:\n  ros__parameters:\n    program: a.ngc\n    fast: true\nother_node:\n  ros__parameters:\n    rate: 7.0\n");
        let (t, o) = parse(&format!("--ros-args -r __ns:=/cell1 -r __node:=m1 --params-file {}", f.path().display())).unwrap();
        assert_eq!((t.program.as_str(), t.rate, t.fast), ("a.ngc", 100.0, true));
        assert_eq!(o.warnings.len(), 1, "the wildcard's unknown parameter is skipped with a warning: {:?}", o.warnings);
        // Nested namespaces and nested parameter names; -p overrides the file; later files override earlier.
        let g = file("cell1:\n  m1:\n    ros__parameters:\n      rate: 300\n      program: b.ngc\n");
        let h = file("/cell1/*:\n  ros__parameters:\n    rate: 400.0\n");
        let (t, _) = parse(&format!("--ros-args -r __ns:=/cell1 -r __node:=m1 --params-file {} --params-file {}", g.path().display(), h.path().display())).unwrap();
        assert_eq!((t.program.as_str(), t.rate), ("b.ngc", 400.0));
        let (t, _) = parse(&format!("--ros-args -r __ns:=/cell1 -r __node:=m1 --params-file {} -p rate:=5.5", g.path().display())).unwrap();
        assert_eq!(t.rate, 5.5);
        // A key naming another node does not apply.
        let (t, _) = parse(&format!("x.ngc --ros-args --params-file {}", g.path().display())).unwrap();
        assert_eq!((t.program.as_str(), t.rate), ("x.ngc", 1000.0));
        let nested = file("/fiveaxis/dflt:\n  ros__parameters:\n    limits:\n      rate: 1.0\n");
        let e = parse(&format!("x --ros-args --params-file {}", nested.path().display())).unwrap_err().to_string();
        assert!(e.contains("limits.rate"), "{e}");
    }

    #[test]
    fn what_cannot_be_used_is_refused_with_its_source() {
        for (args, needle) in [
            ("p --ros-args -p rat:=5.0", "rat (-p rat:=...): not a parameter"),
            ("p --ros-args -p rate:=fast", "parameter rate (-p rate:=...): expected a number"),
            ("p --ros-args -p fast:=1", "expected true or false"),
            ("p --ros-args -p flush_ms:=1.5", "expected an integer"),
            ("p --rate 5 --ros-args -p rate:=6.0", "--rate is 5 on the command line but parameter rate is 6.0"),
            ("p --namespace /a --ros-args -r __ns:=/b", "namespace is '/b' by -r __ns:= and '/a' by --namespace"),
            ("p --ros-args -r __ns:=rel", "must be absolute"),
            ("p --ros-args -p use_sim_time:=1", "parameter use_sim_time (-p use_sim_time:=...): expected true or false"),
            ("p --ros-args --bogus", "--ros-args"),
            ("p --ros-args --params-file /nonexistent/p.yaml", "/nonexistent/p.yaml"),
        ] {
            match parse(args) {
                Err(RosArgsError::Ros(e)) => assert!(e.contains(needle), "{args}: {e}"),
                other => panic!("{args}: {other:?}"),
            }
        }
        // The same value given both ways is not a conflict.
        assert!(parse("p --rate 5 --ros-args -p rate:=5").is_ok());
        let bad = file("/**:\n  ros__parameters: 3\n");
        assert!(matches!(parse(&format!("p --ros-args --params-file {}", bad.path().display())), Err(RosArgsError::Ros(_))));
    }

    /// A tool with subcommands, one of which opens no node (as `fiveaxis-rerun replay`).
    #[derive(Parser, Debug)]
    #[command(name = "s")]
    enum S {
        Replay {
            recording: String,
            #[arg(long, default_value_t = 1.0)]
            scale: f64,
        },
        Live {
            #[command(flatten)]
            common: crate::CommonArgs,
        },
    }

    #[test]
    fn subcommands_take_their_own_parameters_and_names_only_where_they_open_a_node() {
        let (s, o) = parse_from::<S>("n", argv("replay r.mcap --ros-args -p scale:=2.0")).unwrap();
        assert!(matches!(s, S::Replay { ref recording, scale } if recording == "r.mcap" && scale == 2.0), "{s:?}");
        assert_eq!(value(&o, "scale"), ParameterValue::Double(2.0));
        assert!(parse_from::<S>("n", argv("replay r.mcap")).is_ok());
        assert!(matches!(parse_from::<S>("n", argv("replay r.mcap --ros-args -r __ns:=/a")), Err(RosArgsError::Ros(e)) if e.contains("opens no ROS node")));
        let (s, _) = parse_from::<S>("n", argv("live --ros-args -r __ns:=/a -r __node:=m")).unwrap();
        assert!(matches!(s, S::Live { ref common } if common.namespace == "/a" && common.node_name.as_deref() == Some("m")), "{s:?}");
    }

    #[test]
    fn help_lists_every_parameter_with_its_type_and_default() {
        let Err(RosArgsError::Clap(e)) = parse("--help") else { panic!("--help") };
        let help = e.to_string();
        for line in ["rate                         double, default 1000", "fast                         bool, default false", "program                      string, not set by default", "flush_ms                     integer, default 200", "topic                        string_array, default []"] {
            assert!(help.contains(line), "{line} missing from:\n{help}");
        }
    }
}

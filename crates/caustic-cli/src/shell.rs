//! `caustic shell`: the scene language interactively. Each line goes through one
//! [`Interpreter`]; each `render` renders on the device opened at the start and reports; an
//! error prints `<stdin>:LINE:COLUMN: ...` and the session goes on; `exit` or end of input
//! leaves. On a terminal the prompt has line editing and history; piped input is read plainly,
//! so `caustic shell < script.txt` runs a script line by line.

use crate::args::ShellArgs;
use crate::render::check_limits;
use crate::script::{Flow, Host, HostOptions, open_device};
use anyhow::bail;
use caustic_scene::lang::{Interpreter, Location};
use rustyline::DefaultEditor;
use rustyline::error::ReadlineError;
use std::io::{BufRead, IsTerminal};
use std::path::Path;

/// The prompt shown on a terminal.
const PROMPT: &str = "caustic> ";

/// Where lines come from: an editor with history on a terminal, plain lines otherwise.
enum Input {
    Editor(Box<DefaultEditor>),
    Plain(std::io::StdinLock<'static>),
}

impl Input {
    /// The editor when stdin is a terminal, else plain reading.
    fn open() -> anyhow::Result<Input> {
        if std::io::stdin().is_terminal() { Ok(Input::Editor(Box::new(DefaultEditor::new()?))) } else { Ok(Input::Plain(std::io::stdin().lock())) }
    }

    /// The next line, or `None` at the end of input. Ctrl-C at the prompt drops the line.
    fn next_line(&mut self) -> anyhow::Result<Option<String>> {
        match self {
            Input::Editor(editor) => loop {
                match editor.readline(PROMPT) {
                    Ok(line) => {
                        if !line.trim().is_empty() {
                            editor.add_history_entry(line.as_str())?;
                        }
                        return Ok(Some(line));
                    }
                    Err(ReadlineError::Interrupted) => continue,
                    Err(ReadlineError::Eof) => return Ok(None),
                    Err(e) => return Err(e.into()),
                }
            },
            Input::Plain(stdin) => {
                let mut bytes = Vec::new();
                if stdin.read_until(b'\n', &mut bytes)? == 0 {
                    return Ok(None);
                }
                let text = String::from_utf8_lossy(&bytes);
                Ok(Some(text.trim_end_matches(['\n', '\r']).to_string()))
            }
        }
    }

    fn interactive(&self) -> bool {
        matches!(self, Input::Editor(_))
    }
}

/// Runs `caustic shell`. Piped input that had errors ends with a failure status.
pub fn run(args: &ShellArgs) -> anyhow::Result<()> {
    check_limits(args.spp, args.time)?;
    let (ctx, interrupted) = open_device(&args.device)?;
    let options = HostOptions::new(&args.overrides, &args.display, args.spp, args.time, &args.device);
    let mut host = Host::new(&ctx, options, interrupted);
    let mut interpreter = Interpreter::new();
    interpreter.set_scene_name("shell");
    interpreter.set_input_limits(args.overrides.input.limits());
    let mut input = Input::open()?;
    if input.interactive() {
        eprintln!("Caustic scene language: one command a line (docs/SCENE_LANGUAGE.md); `exit` or Ctrl-D leaves.");
    }
    let stdin = Path::new("<stdin>");
    let mut failures = 0usize;
    let mut line_number = 0;
    while let Some(line) = input.next_line()? {
        line_number += 1;
        let actions = interpreter.execute_line(&line, Location::new(stdin, line_number));
        for warning in interpreter.take_warnings() {
            eprintln!("{warning}");
        }
        let actions = match actions {
            Ok(actions) => actions,
            Err(error) => {
                eprintln!("{error}");
                failures += 1;
                continue;
            }
        };
        for action in actions {
            match host.execute(action) {
                Ok(Flow::Continue) => {}
                Ok(Flow::Exit) => return finish(failures, input.interactive()),
                Err(error) => {
                    eprintln!("{}:{line_number}: {error:#}", stdin.display());
                    failures += 1;
                    break;
                }
            }
        }
    }
    finish(failures, input.interactive())
}

/// The end of a session: piped input with errors fails, so scripts notice.
fn finish(failures: usize, interactive: bool) -> anyhow::Result<()> {
    if failures > 0 && !interactive {
        bail!("{failures} line(s) of input failed");
    }
    Ok(())
}

//! `make bench`: one run of a model, for counting its instructions (`benchmarks/instructions.py`
//! runs this under callgrind). Nothing but the run: no timing loop, no output written.
//!
//! Usage: `one_run MODEL.json OPTIONS.json [RUNS]` (SI model, planar or spatial, as
//! `jointgap.Model.to_json()` writes it; options as the engine reads them, e.g. `{"t_end": 0.5, "rate": 10000}`).
//! With RUNS, the same run that many times in the process: the runs after the first take
//! the compiled code from the process's cache, so the difference of two counts is a run
//! without compiling (`benchmarks/compiled.py`).

use jointgap_core::simulate::any::{AnyModel, AnyPrepared};
use jointgap_core::simulate::Silent;
use jointgap_core::{SimOptions, Status};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (model, options, runs) = match args.as_slice() {
        [_, model, options] => (model, options, 1),
        [_, model, options, runs] => (model, options, runs.parse()?),
        _ => return Err("usage: one_run MODEL.json OPTIONS.json [RUNS]".into()),
    };
    let model = AnyModel::from_json(&std::fs::read_to_string(model)?)?;
    let options: SimOptions = serde_json::from_str(&std::fs::read_to_string(options)?)?;
    options.check()?;
    for _ in 0..runs {
        let result = AnyPrepared::new(&model)?.run(&options, &mut Silent, std::time::Instant::now())?;
        if !matches!(result.status, Status::Finished) {
            return Err(format!("the run stopped: {:?}", result.status).into());
        }
        println!("{} steps, {} evaluations", result.stats.accepted_steps, result.stats.rhs_evaluations);
        println!("{}", result.stats.compiled);
    }
    Ok(())
}

//! `make bench`: one run of a model, for counting its instructions (`benchmarks/instructions.py`
//! runs this under callgrind). Nothing but the run: no timing loop, no output written.
//!
//! Usage: `one_run MODEL.json OPTIONS.json` (SI model as `jointgap.Model.to_json()` writes
//! it; options as the engine reads them, e.g. `{"t_end": 0.5, "rate": 10000}`).

use jointgap_core::{simulate, Model, SimOptions, Status};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, model, options] = args.as_slice() else {
        return Err("usage: one_run MODEL.json OPTIONS.json".into());
    };
    let model = Model::from_json(&std::fs::read_to_string(model)?)?;
    let options: SimOptions = serde_json::from_str(&std::fs::read_to_string(options)?)?;
    let result = simulate(&model, &options)?;
    if !matches!(result.status, Status::Finished) {
        return Err(format!("the run stopped: {:?}", result.status).into());
    }
    println!("{} steps, {} evaluations", result.stats.accepted_steps, result.stats.rhs_evaluations);
    println!("{}", result.stats.compiled);
    Ok(())
}

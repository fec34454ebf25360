//! A recorded [`Graph`] compiled to native code in the running process, by Cranelift:
//! one straight-line function that reads the inputs and the parameters, computes every
//! node that an output or a guard needs, stores the outputs and returns whether every
//! guard held. A graph's blocks are compiled apart, each of their ways a function of its
//! own: the graph's code calls [`BlockCode`], which runs the way that held last, then
//! the others, and returns at once where none holds. The
//! arithmetic is the processor's own (add, subtract, multiply, divide, square root,
//! absolute value, negation: exact IEEE operations, as Rust's); the other functions are
//! calls to the very functions the interpreted engine calls, so both give the same bits.
//!
//! Compiled graphs are kept in a process-wide cache by their content: a run, a batch or a
//! study that records the same graph again (the same model, whatever its numbers, on the
//! same path) takes the code compiled before, with its own parameters.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{
    types, AbiParam, InstBuilder, MemFlagsData, StackSlotData, StackSlotKind, Value,
};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module};

use crate::scalar::{Block, Cmp, Func, Graph, Node};

/// The native function of a graph: reads `inputs` and `params`, writes `outputs`, calls
/// its blocks' ways (the fourth argument, its [`BlockCode`]s), returns 1 where every guard
/// held and 0 where one did not (its outputs then mean nothing).
type NativeFn = unsafe extern "C" fn(*const f64, *const f64, *mut f64, *mut BlockCode) -> u8;

/// The compiled ways of one of a graph's blocks, which the graph's code calls.
#[derive(Debug, Clone, Default)]
pub struct BlockCode {
    /// Each way's code and the values of its parameters.
    pub ways: Vec<(Arc<Compiled>, Vec<f64>)>,
    /// The way that held last, tried first.
    pub last: usize,
}

/// Runs the ways of block `b` of `blocks` on the `n_args` numbers at `args`, the way that
/// held last first; writes the first that holds' `n_outs` outputs at `outs` and returns 1,
/// or 0 where none holds.
///
/// # Safety
/// `blocks` points to more than `b` [`BlockCode`]s that nothing else uses during the
/// call, `args` to `n_args` numbers and `outs` to `n_outs`: as the graph's code calls it.
unsafe extern "C" fn jg_block(
    blocks: *mut BlockCode,
    b: u64,
    args: *const f64,
    n_args: u64,
    outs: *mut f64,
    n_outs: u64,
) -> u8 {
    // Safety: as the caller promises.
    let (block, args, outs) = unsafe {
        (
            &mut *blocks.add(b as usize),
            std::slice::from_raw_parts(args, n_args as usize),
            std::slice::from_raw_parts_mut(outs, n_outs as usize),
        )
    };
    let n = block.ways.len();
    for k in (0..n).map(|k| (block.last + k) % n) {
        let (code, params) = &block.ways[k];
        // A way reads a prefix of the block's inputs: those known when it was recorded.
        if code.inputs <= args.len()
            && code.outputs == outs.len()
            && code.call(&args[..code.inputs], params, outs)
        {
            block.last = k;
            return 1;
        }
    }
    0
}

/// A graph's compiled code.
pub struct Compiled {
    function: NativeFn,
    inputs: usize,
    params: usize,
    outputs: usize,
    /// Blocks its code calls.
    blocks: usize,
    /// Owns the code's memory.
    _code: CodeMemory,
    /// Seconds it took to compile.
    pub compile_seconds: f64,
    /// Nodes it computes (after dead ones are dropped).
    pub nodes: usize,
}

/// The code's memory, freed with the [`Compiled`] that holds the only pointer to it.
struct CodeMemory {
    module: Option<JITModule>,
}

// The module is only kept, never used again after compilation: its code is read-only.
unsafe impl Send for CodeMemory {}
unsafe impl Sync for CodeMemory {}

impl Drop for CodeMemory {
    fn drop(&mut self) {
        if let Some(module) = self.module.take() {
            // Safety: the function pointer into this memory lives in the same
            // `Compiled`, which is being dropped: nothing can call it any more.
            unsafe { module.free_memory() };
        }
    }
}

impl std::fmt::Debug for Compiled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Compiled({} nodes, {} -> {})", self.nodes, self.inputs, self.outputs)
    }
}

impl Compiled {
    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// Runs the code of a graph without blocks at `inputs` with parameters `params`:
    /// `outputs` filled and `true` where every guard held.
    #[inline]
    pub fn call(&self, inputs: &[f64], params: &[f64], outputs: &mut [f64]) -> bool {
        self.call_with(inputs, params, outputs, &mut [])
    }

    /// [`Compiled::call`] for a graph whose blocks' ways are `blocks`.
    #[inline]
    pub fn call_with(
        &self,
        inputs: &[f64],
        params: &[f64],
        outputs: &mut [f64],
        blocks: &mut [BlockCode],
    ) -> bool {
        assert!(
            inputs.len() == self.inputs
                && params.len() == self.params
                && outputs.len() == self.outputs
                && blocks.len() == self.blocks,
            "compiled function's sizes"
        );
        // Safety: the function reads `inputs` and `params` entries, writes `outputs`
        // entries and calls `blocks`' ways, whose lengths are checked above; its code
        // lives as long as `self`.
        unsafe {
            (self.function)(inputs.as_ptr(), params.as_ptr(), outputs.as_mut_ptr(), blocks.as_mut_ptr()) == 1
        }
    }
}

/// Why a graph was not compiled.
#[derive(Debug, Clone, PartialEq)]
pub struct CodegenError(pub String);

/// The compiled code of `graph`, from the process's cache or compiled now; the flag says
/// whether it was compiled now.
pub fn compile_cached(graph: &Graph) -> Result<(Arc<Compiled>, bool), CodegenError> {
    static CACHE: OnceLock<Mutex<Cache>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    let code = code_of(graph);
    let key = content_hash(&code);
    if let Some(found) = cache
        .lock()
        .ok()
        .and_then(|c| c.get(&key).and_then(|v| v.iter().find(|(g, _)| *g == code).map(|(_, f)| f.clone())))
    {
        return Ok((found, false));
    }
    let compiled = Arc::new(compile(graph)?);
    if let Ok(mut c) = cache.lock() {
        if c.len() >= CACHE_CAPACITY {
            c.clear();
        }
        c.entry(key).or_default().push((code, compiled.clone()));
    }
    Ok((compiled, true))
}

/// Compiled graphs by their content's hash.
type Cache = HashMap<u64, Vec<(Graph, Arc<Compiled>)>>;

/// Graphs the cache keeps before it starts anew (a calibration records one per
/// parameter set it tries).
const CACHE_CAPACITY: usize = 512;

/// What a graph's code depends on: the graph without its blocks' ways, which are
/// compiled apart.
fn code_of(graph: &Graph) -> Graph {
    let mut code = Graph { blocks: Vec::new(), ..graph.clone() };
    code.blocks = graph.blocks.iter().map(|b| Block { ways: Vec::new(), ..b.clone() }).collect();
    code
}

fn content_hash(graph: &Graph) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    graph.nodes.hash(&mut h);
    graph.guards.hash(&mut h);
    graph.outputs.hash(&mut h);
    graph.inputs.hash(&mut h);
    graph.params.hash(&mut h);
    for b in &graph.blocks {
        b.args.hash(&mut h);
        b.outputs.hash(&mut h);
    }
    h.finish()
}

/// The functions a graph calls, by their symbol names.
const CALLS: [(Func, &str); 8] = [
    (Func::Powf, "jg_powf"),
    (Func::Signum, "jg_signum"),
    (Func::Max, "jg_max"),
    (Func::Min, "jg_min"),
    (Func::Tanh, "jg_tanh"),
    (Func::Cosh, "jg_cosh"),
    (Func::Atan2, "jg_atan2"),
    (Func::RemEuclid, "jg_rem_euclid"),
];

extern "C" fn jg_sin_cos(x: f64, cos: *mut f64) -> f64 {
    let (s, c) = x.sin_cos();
    // Safety: the caller passes its own stack slot of one f64.
    unsafe { *cos = c };
    s
}

macro_rules! callable {
    ($($name:ident => $f:expr),*) => {$(
        extern "C" fn $name(x: f64, y: f64) -> f64 {
            $f.eval(x, y)
        }
    )*};
}

callable!(jg_powf => Func::Powf, jg_signum => Func::Signum, jg_max => Func::Max,
    jg_min => Func::Min, jg_tanh => Func::Tanh, jg_cosh => Func::Cosh, jg_atan2 => Func::Atan2, jg_rem_euclid => Func::RemEuclid);

fn address(f: Func) -> *const u8 {
    match f {
        Func::Sin | Func::Cos => jg_sin_cos as *const u8,
        Func::Powf => jg_powf as *const u8,
        Func::Signum => jg_signum as *const u8,
        Func::Max => jg_max as *const u8,
        Func::Min => jg_min as *const u8,
        Func::Tanh => jg_tanh as *const u8,
        Func::Cosh => jg_cosh as *const u8,
        Func::Atan2 => jg_atan2 as *const u8,
        Func::RemEuclid => jg_rem_euclid as *const u8,
        Func::Implicit(f) => f.value as *const u8,
    }
}

/// The functions computed by methods of their own that `graph` calls, by their names.
fn implicit_functions(graph: &Graph) -> Vec<(Func, &'static str)> {
    let mut found: Vec<(Func, &'static str)> = Vec::new();
    for node in &graph.nodes {
        if let Node::Call(f @ Func::Implicit(i), _, _) = *node {
            if !found.iter().any(|&(g, _)| g == f) {
                found.push((f, i.name));
            }
        }
    }
    found
}

/// Nodes an output, a guard or a block (which every run calls) needs.
fn live(graph: &Graph) -> Vec<bool> {
    let mut live = vec![false; graph.nodes.len()];
    graph.outputs.iter().for_each(|&o| live[o as usize] = true);
    graph.blocks.iter().flat_map(|b| &b.args).for_each(|&a| live[a as usize] = true);
    for g in &graph.guards {
        live[g.a as usize] = true;
        live[g.b as usize] = true;
    }
    for k in (0..graph.nodes.len()).rev() {
        if !live[k] {
            continue;
        }
        match graph.nodes[k] {
            Node::Const(_) | Node::Input(_) | Node::Param(_) | Node::Out(..) => {}
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                live[a as usize] = true;
                live[b as usize] = true;
            }
            Node::Neg(a) | Node::Sqrt(a) | Node::Abs(a) => live[a as usize] = true,
            Node::Call(_, a, b) => {
                live[a as usize] = true;
                if b != u32::MAX {
                    live[b as usize] = true;
                }
            }
        }
    }
    live
}

fn codegen_error(e: impl std::fmt::Display) -> CodegenError {
    CodegenError(format!("native code generation failed: {e}"))
}

/// Compiles `graph` to native code.
pub fn compile(graph: &Graph) -> Result<Compiled, CodegenError> {
    let started = Instant::now();
    let mut flags = settings::builder();
    flags.set("opt_level", "speed").map_err(codegen_error)?;
    // The builder above is the only producer of the IR, and its tests run it: checking
    // every function again costs a third of the compile time.
    flags.set("enable_verifier", "false").map_err(codegen_error)?;
    // Cranelift's backtracking register allocator (its default): against the one-pass
    // allocator it takes about twice the compile time (founding case: 22 ms against
    // 13 ms) for code that runs the founding case 1.19x faster instead of 1.06x, wall
    // time of repeated runs (benchmarks/README.md). Many runs of one model (batches,
    // studies, fitting, wear) are what compiling is for.
    flags.set("regalloc_algorithm", "backtracking").map_err(codegen_error)?;
    let isa = cranelift_native::builder()
        .map_err(codegen_error)?
        .finish(settings::Flags::new(flags))
        .map_err(codegen_error)?;
    let mut jit = JITBuilder::with_isa(isa, default_libcall_names());
    jit.symbol("jg_sin_cos", address(Func::Sin));
    jit.symbol("jg_block", jg_block as *const u8);
    let implicit = implicit_functions(graph);
    for (f, name) in CALLS.into_iter().chain(implicit.iter().copied()) {
        jit.symbol(name, address(f));
    }
    let mut module = JITModule::new(jit);
    let ptr = module.target_config().pointer_type();
    let call_conv = module.isa().default_call_conv();
    let mut declare = |name: &str, params: &[types::Type]| -> Result<FuncId, CodegenError> {
        let mut sig = cranelift_codegen::ir::Signature::new(call_conv);
        sig.params.extend(params.iter().map(|&t| AbiParam::new(t)));
        sig.returns.push(AbiParam::new(types::F64));
        module.declare_function(name, Linkage::Import, &sig).map_err(codegen_error)
    };
    let sin_cos = declare("jg_sin_cos", &[types::F64, ptr])?;
    let mut calls = HashMap::new();
    for (f, name) in CALLS.into_iter().chain(implicit) {
        calls.insert(f, declare(name, &[types::F64, types::F64])?);
    }
    let block_call = {
        let mut sig = cranelift_codegen::ir::Signature::new(call_conv);
        sig.params.extend([ptr, types::I64, ptr, types::I64, ptr, types::I64].map(AbiParam::new));
        sig.returns.push(AbiParam::new(types::I8));
        module.declare_function("jg_block", Linkage::Import, &sig).map_err(codegen_error)?
    };

    let mut ctx = module.make_context();
    for _ in 0..4 {
        ctx.func.signature.params.push(AbiParam::new(ptr));
    }
    ctx.func.signature.returns.push(AbiParam::new(types::I8));
    let live = live(graph);
    let mut fctx = FunctionBuilderContext::new();
    {
        let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
        let block = b.create_block();
        b.append_block_params_for_function_params(block);
        b.switch_to_block(block);
        b.seal_block(block);
        let [input, param, output, blocks] = [0, 1, 2, 3].map(|k| b.block_params(block)[k]);
        let sin_cos_ref = module.declare_func_in_func(sin_cos, b.func);
        let block_ref = module.declare_func_in_func(block_call, b.func);
        // Where a block's inputs are put and its outputs come back.
        let widest = |f: fn(&Block) -> usize| 8 * graph.blocks.iter().map(f).max().unwrap_or(0) as u32;
        let args_slot = b.create_sized_stack_slot(StackSlotData::new(
            StackSlotKind::ExplicitSlot,
            widest(|k| k.args.len()),
            3,
        ));
        let outs_slot = b.create_sized_stack_slot(StackSlotData::new(
            StackSlotKind::ExplicitSlot,
            widest(|k| k.outputs),
            3,
        ));
        let fail = b.create_block();
        let mut outs: Vec<Value> = Vec::new();
        let call_refs: HashMap<Func, _> =
            calls.iter().map(|(&f, &id)| (f, module.declare_func_in_func(id, b.func))).collect();
        let slot = b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 8, 3));
        let flags = MemFlagsData::trusted();
        let mut v: Vec<Option<Value>> = vec![None; graph.nodes.len()];
        // The sine and cosine of one call, by the angle's node.
        let mut pairs: HashMap<u32, (Value, Value)> = HashMap::new();
        for (k, node) in graph.nodes.iter().enumerate() {
            if let Node::Out(at, 0) = *node {
                let site = &graph.blocks[at as usize];
                let args_at = b.ins().stack_addr(ptr, args_slot, 0);
                let outs_at = b.ins().stack_addr(ptr, outs_slot, 0);
                for (i, &a) in site.args.iter().enumerate() {
                    let value = v[a as usize].expect("a block's input computed before it");
                    b.ins().store(flags, value, args_at, (8 * i) as i32);
                }
                let numbers = [at as usize, site.args.len(), site.outputs]
                    .map(|n| b.ins().iconst(types::I64, n as i64));
                let call =
                    b.ins().call(block_ref, &[blocks, numbers[0], args_at, numbers[1], outs_at, numbers[2]]);
                let held = b.inst_results(call)[0];
                let next = b.create_block();
                b.ins().brif(held, next, &[], fail, &[]);
                b.switch_to_block(next);
                b.seal_block(next);
                outs = (0..site.outputs)
                    .map(|o| b.ins().load(types::F64, flags, outs_at, (8 * o) as i32))
                    .collect();
            }
            if !live[k] {
                continue;
            }
            let a = |i: u32| v[i as usize].expect("an argument computed before its use");
            let value = match *node {
                Node::Const(bits) => b.ins().f64const(f64::from_bits(bits)),
                Node::Input(i) => b.ins().load(types::F64, flags, input, (8 * i) as i32),
                Node::Param(i) => b.ins().load(types::F64, flags, param, (8 * i) as i32),
                Node::Add(p, q) => b.ins().fadd(a(p), a(q)),
                Node::Sub(p, q) => b.ins().fsub(a(p), a(q)),
                Node::Mul(p, q) => b.ins().fmul(a(p), a(q)),
                Node::Div(p, q) => b.ins().fdiv(a(p), a(q)),
                Node::Neg(p) => b.ins().fneg(a(p)),
                Node::Sqrt(p) => b.ins().sqrt(a(p)),
                Node::Abs(p) => b.ins().fabs(a(p)),
                Node::Call(f @ (Func::Sin | Func::Cos), p, _) => {
                    let angle = a(p);
                    let (sin, cos) = *pairs.entry(p).or_insert_with(|| {
                        let at = b.ins().stack_addr(ptr, slot, 0);
                        let call = b.ins().call(sin_cos_ref, &[angle, at]);
                        let sin = b.inst_results(call)[0];
                        (sin, b.ins().stack_load(ptr, types::F64, slot, 0))
                    });
                    if f == Func::Sin {
                        sin
                    } else {
                        cos
                    }
                }
                Node::Call(f, p, q) => {
                    let y = if q == u32::MAX { b.ins().f64const(0.0) } else { a(q) };
                    let call = b.ins().call(call_refs[&f], &[a(p), y]);
                    b.inst_results(call)[0]
                }
                Node::Out(_, o) => outs[o as usize],
            };
            v[k] = Some(value);
        }
        let mut ok = b.ins().iconst(types::I8, 1);
        for g in &graph.guards {
            let cc = match g.op {
                Cmp::Lt => FloatCC::LessThan,
                Cmp::Le => FloatCC::LessThanOrEqual,
                Cmp::Gt => FloatCC::GreaterThan,
                Cmp::Ge => FloatCC::GreaterThanOrEqual,
                Cmp::Eq => FloatCC::Equal,
                Cmp::Ne => FloatCC::NotEqual,
            };
            let (x, y) = (v[g.a as usize].expect("a guard's node"), v[g.b as usize].expect("a guard's node"));
            let holds = b.ins().fcmp(cc, x, y);
            let as_recorded = if g.holds { holds } else { b.ins().bxor_imm_u(holds, 1) };
            ok = b.ins().band(ok, as_recorded);
        }
        for (k, &o) in graph.outputs.iter().enumerate() {
            let value = v[o as usize].expect("an output's node");
            b.ins().store(flags, value, output, (8 * k) as i32);
        }
        b.ins().return_(&[ok]);
        b.switch_to_block(fail);
        b.seal_block(fail);
        let none = b.ins().iconst(types::I8, 0);
        b.ins().return_(&[none]);
        b.finalize(module.isa().frontend_config());
    }
    let id =
        module.declare_function("evaluation", Linkage::Export, &ctx.func.signature).map_err(codegen_error)?;
    module.define_function(id, &mut ctx).map_err(codegen_error)?;
    module.clear_context(&mut ctx);
    module.finalize_definitions().map_err(codegen_error)?;
    let code = module.get_finalized_function(id);
    // Safety: the function was built with exactly this signature.
    let function = unsafe { std::mem::transmute::<*const u8, NativeFn>(code) };
    Ok(Compiled {
        function,
        inputs: graph.inputs,
        params: graph.params,
        outputs: graph.outputs.len(),
        blocks: graph.blocks.len(),
        _code: CodeMemory { module: Some(module) },
        compile_seconds: started.elapsed().as_secs_f64(),
        nodes: live.iter().filter(|&&l| l).count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scalar::{c, record, Real, Traced};

    /// Every operation and call, and a branch: the compiled code gives the bits of the
    /// same computation on `f64`.
    fn kernel<T: Real>(x: &[T]) -> Vec<T> {
        let (s, co) = x[0].sin_cos();
        let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let w = if r > 1.0 { r.powf(c(1.5)) } else { (x[1] / r).tanh() };
        vec![
            s * co + x[1],
            w,
            -(x[0] - x[1]).abs() / 3.0,
            x[1].signum() * x[0].cosh(),
            x[0].max(x[1]),
            x[0].min(c(0.25)),
            c::<T>(2.0) * 0.5 + 0.25,
            x[1].atan2(x[0]),
            x[0].rem_euclid(c(0.3)),
        ]
    }

    #[test]
    fn compiled_code_repeats_the_kernel_bit_for_bit() {
        let at = [0.7, 1.3];
        let (graph, p) = record(&at, |x| Some(kernel::<Traced>(x))).expect("a graph");
        let f = compile(&graph).expect("compiles");
        let mut out = vec![0.0; 9];
        for x in [[0.7, 1.3], [-2.1, 0.4], [3.0, -0.0], [1.0, 5e-3]] {
            let ok = f.call(&x, &p, &mut out);
            let expected = kernel::<f64>(&x);
            let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
            assert_eq!(ok, r > 1.0, "{x:?}");
            if ok {
                for (k, (a, b)) in out.iter().zip(&expected).enumerate() {
                    assert_eq!(a.to_bits(), b.to_bits(), "{x:?} output {k}: {a} vs {b}");
                }
            }
            let (graph_ok, graph_out) = graph.eval(&x, &p);
            assert_eq!(graph_ok, ok);
            if ok {
                assert_eq!(graph_out, out);
            }
        }
    }

    /// A graph's code calls its blocks' ways, the one that holds: where none does it
    /// returns at once, and with the way of the other branch added it runs the kernel's
    /// bits there too.
    #[test]
    fn blocks_run_the_way_that_holds() {
        use crate::scalar::traced_tests::blocked;
        let (graph, p) = record(&[0.5, 2.0, 3.0], blocked::<Traced>).expect("a graph");
        let outer = compile(&graph).expect("compiles");
        let mut blocks: Vec<BlockCode> = graph
            .blocks
            .iter()
            .map(|b| BlockCode {
                ways: vec![(Arc::new(compile(&b.ways[0].0).expect("compiles")), b.ways[0].1.clone())],
                last: 0,
            })
            .collect();
        let mut out = [0.0];
        let x = [0.5, 2.0, 3.0];
        assert!(outer.call_with(&x, &p, &mut out, &mut blocks));
        assert_eq!(out[0].to_bits(), blocked::<f64>(&x).expect("a value")[0].to_bits());
        let other = [0.5, -2.0, 3.0];
        assert!(!outer.call_with(&other, &p, &mut out, &mut blocks));
        let (again, _) = record(&other, blocked::<Traced>).expect("a graph");
        let (way, q) = &again.blocks[0].ways[0];
        assert_eq!(again.blocks[0].args, graph.blocks[0].args);
        blocks[0].ways.push((Arc::new(compile(way).expect("compiles")), q.clone()));
        for x in [other, x] {
            assert!(outer.call_with(&x, &p, &mut out, &mut blocks));
            assert_eq!(out[0].to_bits(), blocked::<f64>(&x).expect("a value")[0].to_bits());
        }
    }

    /// The cache returns the code compiled for an equal graph.
    #[test]
    fn equal_graphs_share_their_code() {
        let (graph, _) = record(&[0.3, 0.4], |x| Some(vec![x[0] * x[1] + 17.125])).expect("a graph");
        let (a, first) = compile_cached(&graph).expect("compiles");
        let (b, again) = compile_cached(&graph.clone()).expect("compiles");
        assert!(first && !again);
        assert!(Arc::ptr_eq(&a, &b));
    }
}

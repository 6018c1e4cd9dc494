//! Branches a pipeline's override constants decide, removed before the driver sees them.
//!
//! Each kernel is one program specialised by `override` constants (`SCENE_REQUIRES`,
//! `LOBE_MASK`, the traversal's and integrators' switches): the code a scene does not need
//! sits behind `if` statements whose condition the constants fix. The SPIR-V still carries
//! those branches and every function they call, and lavapipe translates and optimises all of
//! it into NIR on every pipeline creation, warm cache or not, inlining every call, before it
//! folds them away. Here the taken side of each decided `if` or `switch` replaces the
//! statement in the naga module, and a call with constant arguments calls a copy of its
//! function specialised to them (the lobe functions take their slot as a literal), so
//! compaction drops the rest with the functions only it called.
//!
//! A condition is decided when it evaluates, with the pipeline's constant values, from
//! literals, constants, overrides, constant arguments, logical and integer operators, the
//! temporaries of `&&` and `||`, and calls of functions that the constants and their
//! arguments lead, without side effects, to a decided `return` (`scene_needs(bits)`,
//! `lobe_in_scene(slot)`, `inspect_armed()`); such a call becomes its value. Anything else (a
//! value read at run time, a float) leaves the statement as it is. Calls of functions left
//! doing nothing (the pixel inspector's hooks in a kernel that does not inspect) go too, so
//! an edit of code a kernel never runs leaves its SPIR-V, and the driver's cache entry, as
//! they were.

use naga::{Arena, BinaryOperator, Block, Expression, Function, Handle, Literal, LocalVariable, Module, Statement, UnaryOperator};
use std::collections::{HashMap, HashSet, VecDeque};

/// Each call's result expression and the call (callee and arguments) that makes it.
type Calls = HashMap<Handle<Expression>, (Handle<Function>, Vec<Handle<Expression>>)>;

/// A function and the constant values of its arguments (`None`: decided at run time).
type Specialisation = (Handle<Function>, Vec<Option<Value>>);

/// A value the folding computes: the scalars branch conditions are made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Value {
    Bool(bool),
    U32(u32),
    I32(i32),
}

/// `program` with `entry_point` its only entry point, its constants anonymous, and everything
/// that entry point does not reach with the override values `constants` removed. A missing
/// entry point leaves a module without one, which the pipeline's creation reports.
pub fn entry_point_module(program: &naga::Module, entry_point: &str, constants: &[(&str, f64)]) -> naga::Module {
    let mut module = program.clone();
    module.entry_points.retain(|e| e.name == entry_point);
    for (_, constant) in module.constants.iter_mut() {
        constant.name = None;
    }
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    fold(&mut module, constants);
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    module
}

/// Removes from every function of `module` the sides of `if` and `switch` statements that
/// `constants` (override name and value, as wgpu takes them; overrides not named keep their
/// defaults) decide, and the statements after a taken side that ends in a jump. A call with
/// constant arguments calls a copy of its function specialised to them, folded in turn
/// (`pdf_slot(.., 3u)` keeps only slot 3's code, and only if the scene has that lobe).
pub fn fold(module: &mut Module, constants: &[(&str, f64)]) {
    let overrides: HashMap<Handle<naga::Override>, Value> = module
        .overrides
        .iter()
        .filter_map(|(handle, o)| {
            let given = o.name.as_deref().and_then(|name| constants.iter().find(|(n, _)| *n == name)).map(|(_, v)| *v);
            let value = match given {
                Some(v) => from_f64(&module.types[o.ty].inner, v),
                None => o.init.and_then(|init| global_value(module, init)),
            };
            value.map(|v| (handle, v))
        })
        .collect();
    let functions = std::mem::take(&mut module.functions);
    let mut entry_points = std::mem::take(&mut module.entry_points);
    let pending: VecDeque<_> = functions.iter().map(|(handle, _)| handle).collect();
    let mut folder = Folder { module: &*module, overrides: &overrides, functions, specialised: HashMap::new(), pending };
    for entry in &mut entry_points {
        folder.fold_function(&mut entry.function);
    }
    while let Some(handle) = folder.pending.pop_front() {
        let mut function = folder.functions[handle].clone();
        folder.fold_function(&mut function);
        folder.functions[handle] = function;
    }
    let mut functions = folder.functions;
    drop_calls_that_do_nothing(&mut functions, &mut entry_points);
    module.functions = callees_first(functions, &mut entry_points);
    module.entry_points = entry_points;
}

/// Removes every call of a function without a result whose folded body does nothing (the
/// inspector's hooks in a kernel that does not inspect: at most a call of `scene_needs` and a
/// return), until no more go: compaction then drops the functions, so an edit of their code
/// leaves the kernels that never run it as they were (the driver's cache keeps finding them).
fn drop_calls_that_do_nothing(functions: &mut Arena<Function>, entry_points: &mut [naga::EntryPoint]) {
    /// Whether `block` of `function` changes nothing outside the function: it stores only to
    /// local variables, calls only functions of `pure`, and has no loop.
    fn pure_block(function: &Function, block: &Block, pure: &HashSet<Handle<Function>>) -> bool {
        block.iter().all(|statement| match statement {
            Statement::Emit(_) | Statement::Return { .. } | Statement::Break => true,
            Statement::Store { pointer, .. } => matches!(function.expressions[*pointer], Expression::LocalVariable(_)),
            Statement::Call { function: callee, .. } => pure.contains(callee),
            Statement::Block(inner) => pure_block(function, inner, pure),
            Statement::If { accept, reject, .. } => pure_block(function, accept, pure) && pure_block(function, reject, pure),
            Statement::Switch { cases, .. } => cases.iter().all(|case| pure_block(function, &case.body, pure)),
            _ => false,
        })
    }
    fn drop_calls(block: Block, idle: &HashSet<Handle<Function>>, dropped: &mut bool) -> Block {
        let mut out = Block::with_capacity(block.len());
        for (statement, span) in block.span_into_iter() {
            let statement = match statement {
                Statement::Call { function, result: None, .. } if idle.contains(&function) => {
                    *dropped = true;
                    continue;
                }
                Statement::Block(inner) => Statement::Block(drop_calls(inner, idle, dropped)),
                Statement::If { condition, accept, reject } => {
                    Statement::If { condition, accept: drop_calls(accept, idle, dropped), reject: drop_calls(reject, idle, dropped) }
                }
                Statement::Loop { body, continuing, break_if } => {
                    Statement::Loop { body: drop_calls(body, idle, dropped), continuing: drop_calls(continuing, idle, dropped), break_if }
                }
                Statement::Switch { selector, cases } => Statement::Switch {
                    selector,
                    cases: cases.into_iter().map(|case| naga::SwitchCase { body: drop_calls(case.body, idle, dropped), ..case }).collect(),
                },
                other => other,
            };
            out.push(statement, span);
        }
        out
    }
    // A pure function stays pure as calls are dropped, so the set only grows.
    let mut pure = HashSet::new();
    loop {
        loop {
            let found: Vec<_> = functions.iter().filter(|(h, f)| !pure.contains(h) && pure_block(f, &f.body, &pure)).map(|(h, _)| h).collect();
            if found.is_empty() {
                break;
            }
            pure.extend(found);
        }
        let idle: HashSet<_> = pure.iter().copied().filter(|&h| functions[h].result.is_none()).collect();
        let mut dropped = false;
        for function in functions.iter_mut().map(|(_, f)| f).chain(entry_points.iter_mut().map(|e| &mut e.function)) {
            let body = std::mem::take(&mut function.body);
            function.body = drop_calls(body, &idle, &mut dropped);
        }
        if !dropped {
            return;
        }
    }
}

/// `functions` reordered so that each comes after the functions it calls (naga's rule; the
/// specialised copies were appended after their callers), with every call renamed to match.
fn callees_first(functions: Arena<Function>, entry_points: &mut [naga::EntryPoint]) -> Arena<Function> {
    fn visit(handle: Handle<Function>, functions: &Arena<Function>, seen: &mut HashSet<Handle<Function>>, order: &mut Vec<Handle<Function>>) {
        if !seen.insert(handle) {
            return;
        }
        let mut callees = Vec::new();
        for_each_call(&mut functions[handle].body.clone(), &mut |callee| callees.push(*callee));
        for callee in callees {
            visit(callee, functions, seen, order);
        }
        order.push(handle);
    }
    let mut seen = HashSet::new();
    let mut order = Vec::new();
    for (handle, _) in functions.iter() {
        visit(handle, &functions, &mut seen, &mut order);
    }
    let mut sorted = Arena::new();
    let mut renamed = HashMap::new();
    for old in order {
        renamed.insert(old, sorted.append(functions[old].clone(), functions.get_span(old)));
    }
    for function in sorted.iter_mut().map(|(_, f)| f).chain(entry_points.iter_mut().map(|e| &mut e.function)) {
        let mut body = std::mem::take(&mut function.body);
        for_each_call(&mut body, &mut |callee| *callee = renamed[callee]);
        function.body = body;
        for (_, expression) in function.expressions.iter_mut() {
            if let Expression::CallResult(callee) = expression {
                *callee = renamed[callee];
            }
        }
    }
    sorted
}

/// Calls `f` with the callee of every call in `block` and the blocks within it, in the order
/// the statements run: a statement's blocks are visited where it stands, before the statements
/// after it. `callees_first` orders the functions so, and the kernels' SPIR-V follows that order
/// (visiting a block's own calls before its nested blocks' reorders most kernels' functions).
pub fn for_each_call(block: &mut Block, f: &mut dyn FnMut(&mut Handle<Function>)) {
    for statement in block.iter_mut() {
        match statement {
            Statement::Call { function, .. } => f(function),
            Statement::Block(inner) => for_each_call(inner, f),
            Statement::If { accept, reject, .. } => {
                for_each_call(accept, f);
                for_each_call(reject, f);
            }
            Statement::Loop { body, continuing, .. } => {
                for_each_call(body, f);
                for_each_call(continuing, f);
            }
            Statement::Switch { cases, .. } => cases.iter_mut().for_each(|case| for_each_call(&mut case.body, f)),
            _ => {}
        }
    }
}

/// The folding's state: what conditions may read (constants, overrides' values, functions),
/// the specialised copies made so far and the functions still to fold.
struct Folder<'a> {
    module: &'a Module,
    overrides: &'a HashMap<Handle<naga::Override>, Value>,
    functions: Arena<Function>,
    specialised: HashMap<Specialisation, Handle<Function>>,
    pending: VecDeque<Handle<Function>>,
}

impl Folder<'_> {
    fn fold_function(&mut self, function: &mut Function) {
        let body = std::mem::take(&mut function.body);
        function.body = self.fold_block(function, body, &mut HashMap::new());
        // A `let` keeps its expression alive through compaction; the names matter to no driver.
        function.named_expressions.clear();
    }

    /// `block` with its decided `if`s and `switch`es replaced by their taken side, its calls
    /// specialised, and without what follows a jump. `calls` maps each call's result
    /// expression to the call (a call precedes every use of its result).
    fn fold_block(&mut self, function: &mut Function, block: Block, calls: &mut Calls) -> Block {
        let mut out = Block::with_capacity(block.len());
        let mut queue: VecDeque<_> = block.span_into_iter().collect();
        // Local variables whose value the statements just before set (WGSL's `a && b` is an
        // `if` storing into a temporary that the condition then loads).
        let mut known = HashMap::new();
        while let Some((statement, span)) = queue.pop_front() {
            if let Statement::If { condition, accept, reject } = statement {
                match self.evaluate(function, condition, calls, &known) {
                    Some(Value::Bool(taken)) => {
                        let rest = std::mem::take(&mut queue);
                        queue.extend(if taken { accept } else { reject }.span_into_iter());
                        queue.extend(rest);
                    }
                    _ => {
                        known.clear();
                        let accept = self.fold_block(function, accept, calls);
                        let reject = self.fold_block(function, reject, calls);
                        out.push(Statement::If { condition, accept, reject }, span);
                    }
                }
                continue;
            }
            let statement = match statement {
                Statement::Emit(_) => statement,
                Statement::Store { pointer, value } => {
                    if let Expression::LocalVariable(local) = function.expressions[pointer] {
                        match self.evaluate(function, value, calls, &known) {
                            Some(v) => known.insert(local, v),
                            None => known.remove(&local),
                        };
                    }
                    statement
                }
                Statement::Block(inner) => Statement::Block(self.fold_block(function, inner, calls)),
                Statement::Loop { body, continuing, break_if } => {
                    let body = self.fold_block(function, body, calls);
                    let continuing = self.fold_block(function, continuing, calls);
                    Statement::Loop { body, continuing, break_if }
                }
                Statement::Switch { selector, cases } => {
                    // A decided switch keeps the one case taken, as its default: a `break` in
                    // it still leaves the switch.
                    let cases = match self.evaluate(function, selector, calls, &known) {
                        Some(value) => taken_case(cases, value),
                        None => cases,
                    };
                    let cases = cases.into_iter().map(|case| naga::SwitchCase { body: self.fold_block(function, case.body, calls), ..case }).collect();
                    Statement::Switch { selector, cases }
                }
                Statement::Call { function: callee, arguments, result } => {
                    let values: Vec<_> = arguments.iter().map(|&a| self.evaluate(function, a, calls, &known)).collect();
                    if let (Some(result), Some(arguments)) = (result, values.iter().copied().collect::<Option<Vec<_>>>()) {
                        // A call the constants decide (it runs without side effects to a
                        // decided `return`) becomes its value.
                        if let Some(value) = self.call(callee, &arguments) {
                            function.expressions[result] = Expression::Literal(value.literal());
                            continue;
                        }
                    }
                    let callee = if values.iter().any(Option::is_some) { self.specialise(callee, values) } else { callee };
                    if let Some(result) = result {
                        function.expressions[result] = Expression::CallResult(callee);
                        calls.insert(result, (callee, arguments.clone()));
                    }
                    Statement::Call { function: callee, arguments, result }
                }
                other => other,
            };
            if !matches!(statement, Statement::Emit(_) | Statement::Store { .. }) {
                known.clear();
            }
            let jumps = is_jump(&statement);
            out.push(statement, span);
            if jumps {
                break;
            }
        }
        out
    }

    /// The copy of `callee` whose arguments with a value in `values` are those constants
    /// (made and queued for folding the first time it is asked for).
    fn specialise(&mut self, callee: Handle<Function>, values: Vec<Option<Value>>) -> Handle<Function> {
        let key = (callee, values);
        if let Some(&copy) = self.specialised.get(&key) {
            return copy;
        }
        let mut function = self.functions[callee].clone();
        for (_, expression) in function.expressions.iter_mut() {
            if let Expression::FunctionArgument(index) = *expression {
                if let Some(Some(value)) = key.1.get(index as usize) {
                    *expression = Expression::Literal(value.literal());
                }
            }
        }
        function.name = function.name.map(|name| format!("{name}_{}", self.specialised.len()));
        let copy = self.functions.append(function, self.functions.get_span(callee));
        self.specialised.insert(key, copy);
        self.pending.push_back(copy);
        copy
    }

    /// The value of `expression` of `function`, if the constants decide it (`known`: local
    /// variables' values at this point).
    fn evaluate(&self, function: &Function, expression: Handle<Expression>, calls: &Calls, known: &HashMap<Handle<LocalVariable>, Value>) -> Option<Value> {
        let env = Env { locals: known.clone(), results: HashMap::new(), calls: Some(calls) };
        self.value(function, expression, &|_| None, &env)
    }

    /// The value a call of `callee` with `arguments` returns, when the constants and the
    /// arguments decide it: its body run with the branches they decide, through stores to
    /// local variables and calls of such functions, to a `return` of such an expression
    /// (`scene_needs(bits)`; `inspect_armed()`, whose `&&` naga lowers to an `if` storing a
    /// temporary).
    fn call(&self, callee: Handle<Function>, arguments: &[Value]) -> Option<Value> {
        let function = &self.functions[callee];
        let argument = |index: u32| arguments.get(index as usize).copied();
        let mut env = Env::default();
        // Locals start with their initialiser's value (`var on = false;`).
        for (local, variable) in function.local_variables.iter() {
            if let Some(value) = variable.init.and_then(|init| self.value(function, init, &argument, &env)) {
                env.locals.insert(local, value);
            }
        }
        self.run(function, &function.body, &argument, &mut env)?
    }

    /// Runs `block` of `function` as far as the constants decide it: `Some(Some(value))` if it
    /// returns a decided value, `Some(None)` if it ends without returning, `None` where a
    /// statement is not decided (a branch on a run-time value, a store to memory, a loop).
    fn run(&self, function: &Function, block: &Block, argument: &dyn Fn(u32) -> Option<Value>, env: &mut Env) -> Option<Option<Value>> {
        for statement in block.iter() {
            match *statement {
                Statement::Emit(_) => {}
                Statement::Store { pointer, value } => {
                    let Expression::LocalVariable(local) = function.expressions[pointer] else {
                        return None;
                    };
                    match self.value(function, value, argument, env) {
                        Some(v) => env.locals.insert(local, v),
                        None => env.locals.remove(&local),
                    };
                }
                Statement::Call { function: callee, ref arguments, result: Some(result) } => {
                    let values = arguments.iter().map(|&a| self.value(function, a, argument, env)).collect::<Option<Vec<_>>>()?;
                    let value = self.call(callee, &values)?;
                    env.results.insert(result, value);
                }
                Statement::Block(ref inner) => {
                    if let Some(value) = self.run(function, inner, argument, env)? {
                        return Some(Some(value));
                    }
                }
                Statement::If { condition, ref accept, ref reject } => {
                    let Value::Bool(taken) = self.value(function, condition, argument, env)? else {
                        return None;
                    };
                    if let Some(value) = self.run(function, if taken { accept } else { reject }, argument, env)? {
                        return Some(Some(value));
                    }
                }
                Statement::Return { value: Some(value) } => return Some(Some(self.value(function, value, argument, env)?)),
                _ => return None,
            }
        }
        Some(None)
    }

    /// The value of an expression of `function`, its arguments given by `argument` and the
    /// local variables and call results known so far by `env`.
    fn value(&self, function: &Function, expression: Handle<Expression>, argument: &dyn Fn(u32) -> Option<Value>, env: &Env) -> Option<Value> {
        let operand = |e| self.value(function, e, argument, env);
        match function.expressions[expression] {
            Expression::Literal(literal) => from_literal(literal),
            Expression::Constant(constant) => global_value(self.module, self.module.constants[constant].init),
            Expression::Override(o) => self.overrides.get(&o).copied(),
            Expression::FunctionArgument(index) => argument(index),
            Expression::Load { pointer } => match function.expressions[pointer] {
                Expression::LocalVariable(local) => env.locals.get(&local).copied(),
                _ => None,
            },
            Expression::CallResult(callee) => match env.results.get(&expression) {
                Some(&value) => Some(value),
                None => {
                    let (_, arguments) = env.calls?.get(&expression).filter(|(f, _)| *f == callee)?;
                    let values = arguments.iter().map(|&a| operand(a)).collect::<Option<Vec<_>>>()?;
                    self.call(callee, &values)
                }
            },
            Expression::Unary { op, expr } => unary(op, operand(expr)?),
            Expression::Binary { op: BinaryOperator::LogicalAnd, left, right } => match (operand(left), operand(right)) {
                (Some(Value::Bool(false)), _) | (_, Some(Value::Bool(false))) => Some(Value::Bool(false)),
                (Some(Value::Bool(true)), Some(Value::Bool(true))) => Some(Value::Bool(true)),
                _ => None,
            },
            Expression::Binary { op: BinaryOperator::LogicalOr, left, right } => match (operand(left), operand(right)) {
                (Some(Value::Bool(true)), _) | (_, Some(Value::Bool(true))) => Some(Value::Bool(true)),
                (Some(Value::Bool(false)), Some(Value::Bool(false))) => Some(Value::Bool(false)),
                _ => None,
            },
            Expression::Binary { op, left, right } => binary(op, operand(left)?, operand(right)?),
            _ => None,
        }
    }
}

/// What an evaluation knows: local variables' values, the results of the calls
/// [`Folder::run`] has evaluated, and (in the function being folded) the calls that make
/// each call result, evaluated when a condition reads them.
#[derive(Default)]
struct Env<'a> {
    locals: HashMap<Handle<LocalVariable>, Value>,
    results: HashMap<Handle<Expression>, Value>,
    calls: Option<&'a Calls>,
}

impl Value {
    fn literal(self) -> Literal {
        match self {
            Value::Bool(b) => Literal::Bool(b),
            Value::U32(u) => Literal::U32(u),
            Value::I32(i) => Literal::I32(i),
        }
    }
}

/// The case a switch on `value` takes (following merged selectors to their body), alone and
/// as the default.
fn taken_case(cases: Vec<naga::SwitchCase>, value: Value) -> Vec<naga::SwitchCase> {
    let matches = |case: &naga::SwitchCase| match (case.value, value) {
        (naga::SwitchValue::U32(a), Value::U32(b)) => a == b,
        (naga::SwitchValue::I32(a), Value::I32(b)) => a == b,
        _ => false,
    };
    let Some(first) = cases.iter().position(matches).or_else(|| cases.iter().position(|c| c.value == naga::SwitchValue::Default)) else {
        return cases;
    };
    let Some(taken) = cases.into_iter().skip(first).find(|c| !c.fall_through) else {
        return Vec::new();
    };
    vec![naga::SwitchCase { value: naga::SwitchValue::Default, fall_through: false, ..taken }]
}

/// Whether a statement leaves its block (what follows it never runs).
fn is_jump(statement: &Statement) -> bool {
    matches!(statement, Statement::Return { .. } | Statement::Break | Statement::Continue | Statement::Kill)
}

/// The value of a global expression (a constant's or an override's default), if a scalar.
fn global_value(module: &Module, expression: Handle<Expression>) -> Option<Value> {
    match module.global_expressions[expression] {
        Expression::Literal(literal) => from_literal(literal),
        Expression::Constant(constant) => global_value(module, module.constants[constant].init),
        _ => None,
    }
}

fn from_literal(literal: Literal) -> Option<Value> {
    match literal {
        Literal::Bool(b) => Some(Value::Bool(b)),
        Literal::U32(u) => Some(Value::U32(u)),
        Literal::I32(i) => Some(Value::I32(i)),
        _ => None,
    }
}

/// A pipeline constant's value as the override's type takes it (WebGPU's conversion: a
/// bool is true when non-zero; integers must be whole and in range, else left undecided for
/// wgpu to refuse).
fn from_f64(ty: &naga::TypeInner, value: f64) -> Option<Value> {
    match *ty {
        naga::TypeInner::Scalar(naga::Scalar::BOOL) => Some(Value::Bool(value != 0.0)),
        naga::TypeInner::Scalar(naga::Scalar::U32) if value.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(&value) => Some(Value::U32(value as u32)),
        naga::TypeInner::Scalar(naga::Scalar::I32) if value.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&value) => {
            Some(Value::I32(value as i32))
        }
        _ => None,
    }
}

fn unary(op: UnaryOperator, value: Value) -> Option<Value> {
    match (op, value) {
        (UnaryOperator::LogicalNot, Value::Bool(b)) => Some(Value::Bool(!b)),
        (UnaryOperator::BitwiseNot, Value::U32(u)) => Some(Value::U32(!u)),
        (UnaryOperator::BitwiseNot, Value::I32(i)) => Some(Value::I32(!i)),
        (UnaryOperator::Negate, Value::I32(i)) => Some(Value::I32(i.wrapping_neg())),
        _ => None,
    }
}

/// WGSL's integer and comparison operators (wrapping, shifts by the amount modulo 32).
fn binary(op: BinaryOperator, left: Value, right: Value) -> Option<Value> {
    use BinaryOperator as B;
    let value = match (left, right) {
        (Value::U32(a), Value::U32(b)) => match op {
            B::Add => Value::U32(a.wrapping_add(b)),
            B::Subtract => Value::U32(a.wrapping_sub(b)),
            B::Multiply => Value::U32(a.wrapping_mul(b)),
            B::And => Value::U32(a & b),
            B::InclusiveOr => Value::U32(a | b),
            B::ExclusiveOr => Value::U32(a ^ b),
            B::ShiftLeft => Value::U32(a.wrapping_shl(b)),
            B::ShiftRight => Value::U32(a.wrapping_shr(b)),
            _ => Value::Bool(compare(op, a.cmp(&b))?),
        },
        (Value::I32(a), Value::I32(b)) => match op {
            B::Add => Value::I32(a.wrapping_add(b)),
            B::Subtract => Value::I32(a.wrapping_sub(b)),
            B::Multiply => Value::I32(a.wrapping_mul(b)),
            B::And => Value::I32(a & b),
            B::InclusiveOr => Value::I32(a | b),
            B::ExclusiveOr => Value::I32(a ^ b),
            _ => Value::Bool(compare(op, a.cmp(&b))?),
        },
        (Value::I32(a), Value::U32(b)) => match op {
            B::ShiftLeft => Value::I32(a.wrapping_shl(b)),
            B::ShiftRight => Value::I32(a.wrapping_shr(b)),
            _ => return None,
        },
        (Value::Bool(a), Value::Bool(b)) => match op {
            B::Equal => Value::Bool(a == b),
            B::NotEqual => Value::Bool(a != b),
            B::And => Value::Bool(a & b),
            B::InclusiveOr => Value::Bool(a | b),
            _ => return None,
        },
        _ => return None,
    };
    Some(value)
}

fn compare(op: BinaryOperator, ordering: std::cmp::Ordering) -> Option<bool> {
    use std::cmp::Ordering::*;
    Some(match op {
        BinaryOperator::Equal => ordering == Equal,
        BinaryOperator::NotEqual => ordering != Equal,
        BinaryOperator::Less => ordering == Less,
        BinaryOperator::LessEqual => ordering != Greater,
        BinaryOperator::Greater => ordering == Greater,
        BinaryOperator::GreaterEqual => ordering != Less,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PROGRAM: &str = "
        override FEATURES: u32 = 0xffffffffu;
        override FAST: bool = false;
        const SHADOWS: u32 = 0x4u;
        @group(0) @binding(0) var<storage, read_write> out: array<u32>;
        fn needs(bits: u32) -> bool { return (FEATURES & bits) != 0u; }
        fn expensive(x: u32) -> u32 { return x * 7u + 1u; }
        fn shadows(x: u32) -> u32 { return x ^ 0x55u; }
        @compute @workgroup_size(64)
        fn main(@builtin(global_invocation_id) id: vec3<u32>) {
            var v = id.x;
            if needs(SHADOWS) {
                v = shadows(v);
            }
            if FAST && v > 3u {
                out[id.x] = v;
                return;
            }
            if !FAST {
                v = expensive(v);
            } else {
                out[id.x] = v + 1u;
                return;
            }
            out[id.x] = v;
        }";

    /// The names of the functions `main` still calls once folded with `constants` (a
    /// specialised copy's name is its function's).
    fn functions_left(constants: &[(&str, f64)]) -> Vec<String> {
        let mut module = naga::front::wgsl::parse_str(PROGRAM).expect("the program parses");
        fold(&mut module, constants);
        naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .expect("the folded module is valid");
        let mut names: Vec<_> = module
            .functions
            .iter()
            .filter_map(|(_, f)| Some(f.name.as_deref()?.trim_end_matches(|c: char| c.is_ascii_digit()).trim_end_matches('_').to_string()))
            .collect();
        names.sort();
        names.dedup();
        names
    }

    #[test]
    fn decided_branches_go_with_the_functions_only_they_call() {
        // `needs(SHADOWS)` is decided too: its call becomes its value and the function goes.
        assert_eq!(functions_left(&[]), ["expensive", "shadows"], "the defaults take the shadow branch and the slow one");
        assert_eq!(functions_left(&[("FEATURES", 0.0)]), ["expensive"], "no shadows: their branch goes");
        assert_eq!(functions_left(&[("FEATURES", 4.0), ("FAST", 1.0)]), ["shadows"], "fast: the slow branch goes");
    }

    #[test]
    fn a_condition_read_at_run_time_stays() {
        let mut module = naga::front::wgsl::parse_str(PROGRAM).expect("the program parses");
        fold(&mut module, &[("FEATURES", 0.0), ("FAST", 1.0)]);
        let main = &module.entry_points[0].function;
        let ifs = main.body.iter().filter(|s| matches!(s, Statement::If { .. })).count();
        // `FAST && v > 3u` depends on v: naga lowers the short circuit to an `if` on FAST
        // (taken) around one on `v > 3u` (kept); the statements after the taken `else`'s
        // return are gone.
        assert!(ifs >= 1, "the run-time condition was folded away");
        assert!(matches!(main.body.last(), Some(Statement::Return { .. })), "the taken side's return ends the body");
    }

    #[test]
    fn calls_left_doing_nothing_go_and_calls_with_effects_stay() {
        const HOOKS: &str = "
            override TRACE: bool = false;
            var<private> armed: bool;
            @group(0) @binding(0) var<storage, read_write> out: array<u32>;
            fn tracing() -> bool { var on = false; if TRACE { on = armed; } return on; }
            fn record(x: u32) { if !tracing() { return; } out[1] = x; }
            fn arm(x: u32) { if TRACE { armed = x == 3u; } }
            fn touch() { out[2] = 1u; }
            @compute @workgroup_size(1)
            fn main(@builtin(global_invocation_id) id: vec3<u32>) {
                arm(id.x);
                record(id.x);
                touch();
                out[0] = id.x;
            }";
        let names = |trace: f64| {
            let mut module = naga::front::wgsl::parse_str(HOOKS).expect("the program parses");
            fold(&mut module, &[("TRACE", trace)]);
            naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all()).validate(&module).expect("valid");
            let mut names: Vec<_> = module.functions.iter().filter_map(|(_, f)| f.name.clone()).collect();
            names.sort();
            names
        };
        assert_eq!(names(0.0), ["touch"], "without TRACE the hooks do nothing and go; the store stays");
        assert_eq!(names(1.0), ["arm", "record", "touch", "tracing"], "with TRACE the hooks stay");
    }
}

//! Print a file's parameters: `cargo run -p c3d --example params FILE [GROUP]`.
fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: params FILE [GROUP]");
        std::process::exit(2);
    };
    let group = args.next();
    match c3d::read_file(&path) {
        Ok(c) => {
            for g in c.parameters.groups() {
                if group
                    .as_deref()
                    .is_some_and(|w| !w.eq_ignore_ascii_case(&g.name))
                {
                    continue;
                }
                println!(
                    "{} (#{}){}",
                    g.name,
                    g.id,
                    if g.locked { " locked" } else { "" }
                );
                for p in c.parameters.parameters_of(g.id) {
                    let v = match &p.value {
                        c3d::Value::Char(_) => format!("{:?}", p.as_strings()),
                        _ => format!("{:?}", p.as_f32s()),
                    };
                    let v: String = v.chars().take(160).collect();
                    println!("  {:<20} {:?} {}", p.name, p.dims, v);
                }
            }
        }
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(2);
        }
    }
}

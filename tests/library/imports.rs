//! No import circles, file by file: reading the source's own imports
//! (`use crate::...`, `use super::...`, `self::` and paths written
//! `crate::a::b` / `super::a` in code; not a `#[cfg(doc)]` import, which
//! only serves the documentation's links), no module of `src/` imports one
//! that imports it back. An import of a name a module re-exports (`pub use
//! spec::BodySpec` in `scene/physics/mod.rs`) counts as an import of the
//! file that defines it; a module's own submodules (its structure) are not
//! imports of it.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// Every `.rs` file under `root`, by module path (`src/scene/mod.rs` is
/// `scene`, `src/lib.rs` the root).
fn modules(root: &Path) -> BTreeMap<Module, PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(root, &mut files);
    files
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(root).unwrap().with_extension("");
            let mut m: Module = rel.iter().map(|c| c.to_string_lossy().into()).collect();
            if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                m.pop();
            }
            (m, p)
        })
        .collect()
}

/// The text without comments, strings and character literals.
fn code(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                i += 1;
            }
            i += 2;
        } else if c == 'r'
            && (next == Some('"') || next == Some('#'))
            && !b
                .get(i.wrapping_sub(1))
                .is_some_and(|p| p.is_alphanumeric() || *p == '_')
        {
            // a raw string r"..." or r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (1..=hashes).all(|k| b.get(j + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                i += if b[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // a character literal ('"', '\'', 'x'), else a lifetime
            if next == Some('\\') {
                i += 2;
                while i < b.len() && b[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if b.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The paths of a use tree, whitespace removed (`x as y` written `x@y`):
/// `a::{b,c::{d,e@f}}` gives `a::b`, `a::c::d`, `a::c::e@f`.
fn use_paths(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let mut depth = 0;
    let mut items = vec![String::new()];
    for ch in tree.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        if ch == ',' && depth == 0 {
            items.push(String::new());
        } else if let Some(last) = items.last_mut() {
            last.push(ch);
        }
    }
    for item in items {
        let item: String = item.chars().filter(|c| !c.is_whitespace()).collect();
        if item.is_empty() {
            continue;
        }
        let join = |a: &str, b: &str| match (a.is_empty(), b.is_empty()) {
            (true, _) => b.to_string(),
            (_, true) => a.to_string(),
            _ => format!("{a}::{b}"),
        };
        if let (Some(open), true) = (item.find('{'), item.ends_with('}')) {
            let head = item[..open].trim_end_matches("::");
            use_paths(&join(prefix, head), &item[open + 1..item.len() - 1], out);
        } else {
            out.push(join(prefix, &item));
        }
    }
}

/// The `use` statements (each tree expanded) and the `crate::`,
/// `super::` and `self::` paths written in code.
fn imports(code: &str) -> (Vec<String>, Vec<String>) {
    // imports for the documentation's links only are left out
    let mut code = code.to_string();
    while let Some(at) = code.find("#[cfg(doc)]") {
        let end = code[at..].find(';').map_or(code.len(), |e| at + e + 1);
        code.replace_range(at..end, "");
    }
    let code = code.as_str();
    let words = |s: &str, at: usize, w: &str| {
        s[at..].starts_with(w)
            && !s[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':')
            && !s[at + w.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
    };
    let (mut all, mut public) = (Vec::new(), Vec::new());
    let mut i = 0;
    while let Some(k) = code[i..].find("use") {
        let at = i + k;
        i = at + 3;
        if !words(code, at, "use") {
            continue;
        }
        let Some(end) = code[at..].find(';') else {
            break;
        };
        let tree = &code[at + 3..at + end];
        let mut paths = Vec::new();
        // `use a as b` with spaces kept, then whitespace dropped
        let tree: String = tree
            .split_whitespace()
            .map(|w| if w == "as" { " as " } else { w })
            .collect::<Vec<_>>()
            .join("");
        use_paths("", &tree.replace(" as ", "@"), &mut paths);
        let paths: Vec<String> = paths
            .into_iter()
            .map(|p| p.split('@').next().unwrap_or("").to_string())
            .collect();
        let before = code[..at].trim_end();
        if before.ends_with("pub") || before.ends_with(')') && before.contains("pub(") {
            public.extend(paths.iter().cloned());
        }
        all.extend(paths);
    }
    for root in ["crate::", "super::", "self::"] {
        let mut i = 0;
        while let Some(k) = code[i..].find(root) {
            let at = i + k;
            i = at + root.len();
            if !words(code, at, root.trim_end_matches(':')) {
                continue;
            }
            let end = code[at..]
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .map_or(code.len(), |e| at + e);
            all.push(code[at..end].trim_end_matches(':').to_string());
        }
    }
    (all, public)
}

/// The module a path written in `here` names, as segments.
fn absolute(here: &Module, path: &str) -> Module {
    let mut parts: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
    let mut base: Module = match parts.first() {
        Some(&"crate") => {
            parts.remove(0);
            Vec::new()
        }
        Some(&"self") => {
            parts.remove(0);
            here.clone()
        }
        Some(&"super") => {
            let mut b = here.clone();
            while parts.first() == Some(&"super") {
                parts.remove(0);
                b.pop();
            }
            b
        }
        // an external crate or a name in scope: the module's own child
        _ => here.clone(),
    };
    base.extend(parts.iter().map(|s| s.to_string()));
    base
}

/// Module to the modules it imports, every one of them a file of `root`.
fn graph(
    root: &Path,
) -> (
    BTreeMap<Module, PathBuf>,
    BTreeMap<Module, BTreeSet<Module>>,
) {
    let mods = modules(root);
    let longest = |path: &Module| -> Option<(Module, Option<String>)> {
        (0..=path.len()).rev().find_map(|k| {
            let m = path[..k].to_vec();
            mods.contains_key(&m).then(|| (m, path.get(k).cloned()))
        })
    };
    let texts: HashMap<Module, String> = mods
        .iter()
        .map(|(m, p)| (m.clone(), code(&std::fs::read_to_string(p).unwrap())))
        .collect();
    // names re-exported by a module, to the module they come from
    let mut reexports: HashMap<(Module, String), Module> = HashMap::new();
    for (m, text) in &texts {
        for p in imports(text).1 {
            let full = absolute(m, &p);
            if let Some((t, _)) = longest(&full) {
                if &t != m {
                    if let Some(name) = full.last() {
                        reexports.insert((m.clone(), name.clone()), t);
                    }
                }
            }
        }
    }
    let resolve = |full: &Module| -> Option<Module> {
        let (mut t, mut name) = longest(full)?;
        for _ in 0..8 {
            match name
                .as_ref()
                .and_then(|n| reexports.get(&(t.clone(), n.clone())))
            {
                Some(next) => {
                    t = next.clone();
                    name = full.last().cloned();
                }
                None => break,
            }
        }
        Some(t)
    };
    let mut edges = BTreeMap::new();
    for (m, text) in &texts {
        let mut deps = BTreeSet::new();
        for p in imports(text).0 {
            let Some(t) = resolve(&absolute(m, &p)) else {
                continue;
            };
            // a module's own submodules are its structure, not imports
            if t != *m && !t.starts_with(m) {
                deps.insert(t);
            }
        }
        edges.insert(m.clone(), deps);
    }
    (mods, edges)
}

/// The circles of files that import each other, directly or through
/// others: every strongly connected set of more than one file (Tarjan),
/// its files joined by ` <-> `, in order.
fn circles(root: &Path) -> Vec<String> {
    let (mods, edges) = graph(root);
    let nodes: Vec<&Module> = mods.keys().collect();
    let at: HashMap<&Module, usize> = nodes.iter().enumerate().map(|(i, m)| (*m, i)).collect();
    let next: Vec<Vec<usize>> = nodes
        .iter()
        .map(|m| {
            edges
                .get(*m)
                .into_iter()
                .flatten()
                .filter_map(|d| at.get(d).copied())
                .collect()
        })
        .collect();
    struct Tarjan<'a> {
        next: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        stack: Vec<usize>,
        on: Vec<bool>,
        count: usize,
        found: Vec<Vec<usize>>,
    }
    impl Tarjan<'_> {
        fn visit(&mut self, v: usize) {
            self.index[v] = Some(self.count);
            self.low[v] = self.count;
            self.count += 1;
            self.stack.push(v);
            self.on[v] = true;
            for &w in &self.next[v] {
                match self.index[w] {
                    None => {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    }
                    Some(i) if self.on[w] => self.low[v] = self.low[v].min(i),
                    Some(_) => {}
                }
            }
            if Some(self.low[v]) == self.index[v] {
                let mut set = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on[w] = false;
                    set.push(w);
                    if w == v {
                        break;
                    }
                }
                if set.len() > 1 {
                    set.sort_unstable();
                    self.found.push(set);
                }
            }
        }
    }
    let n = nodes.len();
    let mut t = Tarjan {
        next: &next,
        index: vec![None; n],
        low: vec![0; n],
        stack: Vec::new(),
        on: vec![false; n],
        count: 0,
        found: Vec::new(),
    };
    for v in 0..n {
        if t.index[v].is_none() {
            t.visit(v);
        }
    }
    let mut out: Vec<String> = t
        .found
        .iter()
        .map(|set| {
            let name = |i: usize| mods[nodes[i]].display().to_string();
            let ties: Vec<String> = set
                .iter()
                .flat_map(|&a| {
                    next[a]
                        .iter()
                        .filter(|b| set.contains(b))
                        .map(move |&b| format!("\n  {} -> {}", name(a), name(b)))
                })
                .collect();
            let files: Vec<String> = set.iter().map(|&i| name(i)).collect();
            format!("{}{}", files.join(" <-> "), ties.concat())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn no_module_of_the_library_imports_one_that_imports_it_back() {
    let found = circles(Path::new("src"));
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

#[test]
fn no_module_of_the_python_bindings_imports_one_that_imports_it_back() {
    let found = circles(Path::new("python/src"));
    assert!(found.is_empty(), "import circles:\n{}", found.join("\n"));
}

/// The checker finds what it is for: a planted circle, through a
/// re-export and a `super::super::` path, and not a parent's use of its
/// own child.
#[test]
fn the_checker_finds_a_planted_circle() {
    let dir = crate::common::temp_path("imports");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a/b")).unwrap();
    let write = |p: &str, t: &str| std::fs::write(dir.join(p), t).unwrap();
    write("lib.rs", "mod a;\nmod c;\n");
    write("a/mod.rs", "mod b;\npub use b::Thing; // use crate::c;\n");
    write(
        "a/b/mod.rs",
        "mod d;\nuse super::super::c::{self as cc, Other};\npub struct Thing;\n",
    );
    write(
        "a/b/d.rs",
        "use super::Thing;\nlet s = \"use crate::c;\";\n",
    );
    write("c.rs", "use crate::a::Thing;\npub struct Other;\n");
    let found = circles(&dir);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with(&format!(
            "{} <-> {}\n",
            dir.join("a/b/mod.rs").display(),
            dir.join("c.rs").display()
        )),
        "{found:?}"
    );
    // a circle of three files, none importing another back directly
    write("c.rs", "use crate::e::Far;\npub struct Other;\n");
    write("e.rs", "pub use crate::a::Thing as Far;\n");
    write("lib.rs", "mod a;\nmod c;\nmod e;\n");
    let found = circles(&dir);
    assert_eq!(found.len(), 1, "{found:?}");
    for f in ["a/b/mod.rs", "c.rs", "e.rs"] {
        assert!(
            found[0].contains(&dir.join(f).display().to_string()),
            "{f}: {found:?}"
        );
    }
    write("lib.rs", "mod a;\nmod c;\n");
    let _ = std::fs::remove_file(dir.join("e.rs"));
    // without the circle's other half (an import for doc links only is
    // none), nothing
    write(
        "c.rs",
        "#[cfg(doc)]\nuse crate::a::Thing;\npub struct Other;\n",
    );
    assert!(circles(&dir).is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#!/usr/bin/env bash
# Counts the public items of the packbed library (crates/packbed/src), by
# grep, so that it runs on stable Rust (rustdoc's JSON output, which would
# count exactly what is reachable, needs nightly). Issue 62: the size of the
# library's front door, to watch it over time.
#
# How it counts (one declaration = one line):
# - an item is a declaration starting `pub ` (not `pub(crate)`, `pub(super)`,
#   `pub(in ..)`) followed by fn, struct, enum, trait, type, const, static,
#   mod or union (`pub const fn`, `pub unsafe fn`, .. count as fn);
#   `pub fn` at column 0 is a free function, indented it is a method in an
#   `impl` block;
# - `pub use` re-exports are counted apart (each line once, whatever it lists);
# - a field is a line `pub name: Type` (named fields), plus the `pub` fields
#   of tuple structs on their `pub struct` line;
# - comments are skipped, and so are inline private modules (`mod tests {`):
#   their `pub` items are for the tests;
# - two scopes: "all" is every file of the library (reached from lib.rs by
#   `mod`, test modules left out), reachable or not; "named" is what a user
#   can name: the files reached from lib.rs through `pub mod` declarations
#   and through modules re-exported whole (`pub use ensemble::slurm;`,
#   `pub use jobs::*;`), all their `pub` items, plus the items these files
#   re-export one by one from private modules (`pub use analysis::{analyze,
#   Summary}`): each such name once, of the kind of its declaration, with,
#   for a struct, enum or union, the `pub` methods of its inherent `impl`
#   blocks and its `pub` fields in the file that declares it (issue 62: the
#   modules became private and the root re-exports; before, "named" left
#   re-exported items out). A `pub` item of a named file may still be
#   unnamable (a private type's method), and a re-exported type's `impl`
#   blocks in other files are not seen: read "named" as a close estimate of
#   the API a user can name. Types reached only through public fields and
#   signatures (a measure's summary inside `Summary`) are not named, and
#   not counted; --rustdoc counts them.
#
# With --rustdoc it also counts what rustdoc's JSON output holds (the items
# a user can reach by path, through a re-export, or through the fields and
# signatures of those):
# that needs a nightly toolchain (`rustup toolchain install nightly`) and
# python3, takes a check build, and reads JSON format version 57 (older or
# newer nightlies may name things differently).
#
# Usage: scripts/count-public-items.sh [--rustdoc] [SRC_DIR]   (default crates/packbed/src)
set -euo pipefail
cd "$(dirname "$0")/.."
RUSTDOC=0
if [[ "${1:-}" == --rustdoc ]]; then
    RUSTDOC=1
    shift
fi
SRC="${1:-crates/packbed/src}"
[[ -f "$SRC/lib.rs" ]] || { echo "no lib.rs in $SRC" >&2; exit 2; }

# The files of the library reachable from lib.rs: through `pub mod`, or a
# module re-exported whole (`pub use ensemble::compare;`, `pub use jobs::*;`)
# ($1 = pub), or through any `mod` but those under `#[cfg(test)]` ($1 = any).
# Other attributes, such as `#[cfg(feature = "render")]`, are ignored: counted.
lib_files() {
    local queue=("$SRC/lib.rs") file dir name pattern seen=" "
    if [[ "$1" == pub ]]; then
        pattern='^[[:space:]]*pub (mod [a-z_0-9]+|use [a-z_0-9:]+(::\*)?);.*'
    else
        pattern='^[[:space:]]*(pub(\([^)]*\))? )?mod ([a-z_0-9]+);.*'
    fi
    while ((${#queue[@]})); do
        file="${queue[0]}"
        queue=("${queue[@]:1}")
        [[ "$seen" == *" $file "* ]] && continue
        seen+="$file "
        echo "$file"
        case "$file" in
            */lib.rs | */mod.rs) dir="$(dirname "$file")" ;;
            *) dir="${file%.rs}" ;;
        esac
        while read -r name; do
            # A `use` path: from the crate's root (`crate::`) or from here.
            [[ "$name" == crate/* ]] && name="${name#crate/}" && base="$SRC" || base="$dir"
            if [[ -f "$base/$name.rs" ]]; then
                queue+=("$base/$name.rs")
            elif [[ -f "$base/$name/mod.rs" ]]; then
                queue+=("$base/$name/mod.rs")
            fi
        done < <(awk -v pat="$pattern" '
            /^[[:space:]]*#\[cfg\(test\)\]/ { test = 1; next }
            /^[[:space:]]*#\[/ { next }
            {
                if (!test && $0 ~ pat) {
                    sub(/;.*/, ""); name = $NF; sub(/::\*$/, "", name); gsub(/::/, "/", name)
                    print name
                }
                test = 0
            }' "$file")
    done
}

# The items re-exported one by one (`pub use a::{B, c}`) by the files on
# stdin, declared in files of the library that are not on stdin (the
# others count already): each name once, by the kind of its declaration
# (the first top-level `pub` declaration of that name in the library, one
# under the `use` path's module preferred), plus, for a struct, enum or
# union, the `pub fn` of its inherent `impl` blocks and its `pub` fields in
# the file that declares it. Prints "kind count" lines, as count() does.
reexported() {
    local named_list all_list
    named_list="$(mktemp)" all_list="$(mktemp)"
    cat >"$named_list"
    lib_files any | sort -u >"$all_list"
    awk -v named_list="$named_list" -v all_list="$all_list" '
        function leaf(path, file,    name, hint, at, k, best, c, parts, n) {
            sub(/^[[:space:]]+/, "", path); sub(/[[:space:]]+$/, "", path)
            sub(/[[:space:]]+as[[:space:]].*/, "", path)
            if (path == "" || path ~ /(^|::)self$/ || path ~ /\*$/) return
            n = split(path, parts, "::"); name = parts[n]; hint = (n > 1) ? parts[n - 1] : ""
            if (!(name in decls) && (name in alias)) name = alias[name]
            if (!(name in decls)) { unresolved = unresolved " " name " (" file ")"; return }
            # The declaration: one under the module the path names, else the first.
            split(decls[name], c, "\n"); best = c[2]
            for (k = 2; k in c; k++) if (hint != "" && (c[k] ~ ("/" hint "(/|\\.rs)"))) { best = c[k]; break }
            if (best in named) return
            if ((best SUBSEP name) in done) return
            done[best, name] = 1
            k = kind[best, name]; n_[k]++
            n_["fn (method)"] += methods[best, name]
            n_["field"] += fields[best, name]
        }
        BEGIN {
            while ((getline f < named_list) > 0) named[f] = 1
            # Every top-level `pub` declaration of the library, its methods and fields.
            while ((getline f < all_list) > 0) {
                type = ""; impl = ""
                while ((getline line < f) > 0) {
                    if (line ~ /^}/) { type = ""; impl = ""; continue }
                    if (impl != "" && line ~ /^    pub (const |async |unsafe )*fn /) methods[f, impl]++
                    if (type != "" && line ~ /^    pub [a-z_][a-z_0-9]*[[:space:]]*:/) fields[f, type]++
                    if (line ~ /^impl(<[^>]*>)? [A-Za-z_0-9]+(<[^{]*>)?( where .*)? \{$/) {
                        t = line; sub(/^impl(<[^>]*>)? /, "", t); sub(/[<[:space:]].*/, "", t); impl = t
                        continue
                    }
                    # A re-export under another name, for chains of re-exports.
                    if (line ~ /^pub use [A-Za-z_0-9:]+ as [A-Za-z_0-9]+;/) {
                        t = line; sub(/;.*/, "", t); split(t, w, " ")
                        sub(/.*::/, "", w[3]); alias[w[5]] = w[3]
                    }
                    if (line !~ /^pub (const |async |unsafe |extern "[^"]*" )*(fn|struct|enum|trait|type|const|static|union|mod) /) continue
                    t = line; sub(/^pub /, "", t)
                    # `const NAME: T` is a constant, `const fn` a function.
                    if (t !~ /^const [A-Za-z_0-9]+[[:space:]]*:/) sub(/^(const |async |unsafe |extern "[^"]*" )*/, "", t)
                    k = t; sub(/ .*/, "", k); sub(/^[a-z]+ /, "", t); sub(/[^A-Za-z_0-9].*/, "", t)
                    if (k == "fn") k = "fn (free)"
                    if (k == "mod") continue
                    decls[t] = decls[t] "\n" f; kind[f, t] = k
                    if (k == "struct") {
                        tail = line; nf = gsub(/[(,][[:space:]]*pub [^(]/, "", tail); fields[f, t] += nf
                        if (line ~ /\{$/) type = t
                    }
                    if (k == "enum" || k == "union") if (line ~ /\{$/) type = ""
                }
                close(f)
            }
            # The `pub use` statements of the named files, split into leaves.
            for (f in named) {
                stmt = ""; inuse = 0; test = 0
                while ((getline line < f) > 0) {
                    if (line ~ /^[[:space:]]*#\[cfg\(test\)\]/) { test = 1; continue }
                    if (!inuse && line ~ /^[[:space:]]*pub use /) {
                        if (test) { test = 0; continue }
                        inuse = 1; stmt = ""
                    }
                    if (line !~ /^[[:space:]]*#\[/) test = 0
                    if (!inuse) continue
                    stmt = stmt " " line
                    if (line !~ /;/) continue
                    inuse = 0
                    sub(/^[[:space:]]*pub use /, "", stmt); sub(/;.*/, "", stmt)
                    # A module re-exported whole counts as a named file.
                    if (stmt !~ /[{]/ && stmt ~ /(^|::)[a-z_0-9]+[[:space:]]*$/) continue
                    depth = 0; prefix[0] = ""; cur = ""
                    while (match(stmt, /[{},]/)) {
                        cur = cur substr(stmt, 1, RSTART - 1); ch = substr(stmt, RSTART, 1)
                        stmt = substr(stmt, RSTART + 1)
                        if (ch == "{") { depth++; prefix[depth] = prefix[depth - 1] cur; cur = "" }
                        else {
                            if (cur ~ /[A-Za-z_]/) { p = prefix[depth] cur; gsub(/[[:space:]]+/, " ", p); gsub(/ ?:: ?/, "::", p); leaf(p, f) }
                            cur = ""
                            if (ch == "}") depth--
                        }
                    }
                    cur = cur stmt
                    if (cur ~ /[A-Za-z_]/) { p = prefix[depth] cur; gsub(/[[:space:]]+/, " ", p); gsub(/ ?:: ?/, "::", p); leaf(p, f) }
                }
                close(f)
            }
            if (unresolved != "") print "re-exports not found:" unresolved > "/dev/stderr"
            split("fn (free)|fn (method)|struct|enum|trait|type|const|static|mod|union|field", kinds, "|")
            for (k = 1; k in kinds; k++) printf "%s\t%d\n", kinds[k], n_[kinds[k]]
        }'
    rm -f "$named_list" "$all_list"
}

# Counts over the files given on stdin; prints "kind count" lines.
count() {
    xargs awk '
        FNR == 1 { skip = 0 }
        {
            line = $0
            if (line ~ /^[[:space:]]*\/\//) next
            # Strings and char literals hold braces that are no blocks.
            gsub(/"([^"\\]|\\.)*"/, "\"\"", line)
            gsub(/'"'"'[{}]'"'"'/, "", line)
            opens = gsub(/\{/, "{", line); closes = gsub(/\}/, "}", line)
            if (skip) { depth += opens - closes; if (depth <= 0) skip = 0; next }
            if (line ~ /^[[:space:]]*(pub\([^)]*\)[[:space:]]+)?mod [a-z_0-9]+[[:space:]]*\{/) {
                skip = 1; depth = opens - closes; if (depth <= 0) skip = 0; next
            }
            if (line ~ /^pub (const |async |unsafe |extern "[^"]*" )*fn /) n["fn (free)"]++
            else if (line ~ /^[[:space:]]+pub (const |async |unsafe |extern "[^"]*" )*fn /) n["fn (method)"]++
            else if (line ~ /^[[:space:]]*pub struct /) {
                n["struct"]++
                t = line; f = gsub(/[(,][[:space:]]*pub [^(]/, "", t); if (f) n["field"] += f
            }
            else if (line ~ /^[[:space:]]*pub enum /) n["enum"]++
            else if (line ~ /^[[:space:]]*pub (unsafe )?trait /) n["trait"]++
            else if (line ~ /^[[:space:]]*pub type /) n["type"]++
            else if (line ~ /^[[:space:]]*pub const /) n["const"]++
            else if (line ~ /^[[:space:]]*pub static /) n["static"]++
            else if (line ~ /^[[:space:]]*pub mod /) n["mod"]++
            else if (line ~ /^[[:space:]]*pub union /) n["union"]++
            else if (line ~ /^[[:space:]]*pub use /) n["use (re-export)"]++
            else if (line ~ /^[[:space:]]*pub [a-z_][a-z_0-9]*[[:space:]]*:/) n["field"]++
        }
        END {
            split("fn (free)|fn (method)|struct|enum|trait|type|const|static|mod|union", kinds, "|")
            for (k = 1; k in kinds; k++) { printf "%s\t%d\n", kinds[k], n[kinds[k]]; items += n[kinds[k]] }
            printf "items\t%d\n", items
            printf "use (re-export)\t%d\n", n["use (re-export)"]
            printf "field\t%d\n", n["field"]
        }'
}

all="$(lib_files any | sort -u)"
named="$(lib_files pub | sort -u)"
# The named scope: the named files' items plus the items they re-export.
named_counts="$(
    awk -F'\t' 'NR == FNR { extra[$1] = $2; next }
        $1 == "items" { next }
        { n = $2 + extra[$1]; print $1 "\t" n }
        $1 == "union" { items = 0 }' <(reexported <<<"$named") <(count <<<"$named") |
        awk -F'\t' '{ print } $1 !~ /^(use|field)/ { items += $2 }
            $1 == "union" { print "items\t" items }'
)"
echo "packbed's public items in $SRC (the comment of scripts/count-public-items.sh says how it counts)"
paste <(printf 'kind\tall\n'; printf 'files\t%d\n' "$(wc -l <<<"$all")"; count <<<"$all") \
    <(printf 'named\n%d\n' "$(wc -l <<<"$named")"; cut -f2 <<<"$named_counts") |
    awk -F'\t' '{ printf "%-16s %6s %6s\n", $1, $2, $3 }'

((RUSTDOC)) || exit 0
echo
echo "rustdoc's JSON (cargo +nightly rustdoc -p packbed --lib, reachable items only)"
TARGET="${CARGO_TARGET_DIR:-target}"
cargo +nightly rustdoc -q -p packbed --lib -- -Z unstable-options --output-format json
python3 - "$TARGET/doc/packbed.json" <<'PY'
import collections, json, sys

doc = json.load(open(sys.argv[1]))
index = doc["index"]
kind = lambda item: next(iter(item["inner"]))
local = {i: item for i, item in index.items() if item.get("crate_id") == 0}
# Methods: the items of inherent impls (not trait impls, whose methods the
# trait documents).
inherent = set()
for item in local.values():
    if kind(item) == "impl" and item["inner"]["impl"].get("trait") is None:
        inherent.update(str(m) for m in item["inner"]["impl"]["items"])
n = collections.Counter()
for i, item in local.items():
    k, public = kind(item), item.get("visibility") == "public"
    if k == "function" and i in inherent:
        n["fn (method)"] += public
    elif k == "function" and i in doc["paths"]:
        n["fn (free)"] += 1
    elif k == "struct_field":
        n["field"] += public
    elif k in ("struct", "enum", "trait", "type_alias", "constant", "static", "module", "union", "use"):
        n[k] += 1
rows = ["fn (free)", "fn (method)", "struct", "enum", "trait", "type_alias", "constant", "static", "module", "union"]
for k in rows:
    print(f"{k:16} {n[k]:6}")
print(f"{'items':16} {sum(n[k] for k in rows):6}")
print(f"{'use (re-export)':16} {n['use']:6}")
print(f"{'field':16} {n['field']:6}")
PY

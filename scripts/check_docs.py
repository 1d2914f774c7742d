#!/usr/bin/env python3
"""The docs name only what exists (ctest Docs.NameOnlyWhatExists). In every Markdown file of
the repository (docs/, the top level, traces/, rtl_model/), outside code blocks:
- a relative link [text](path#anchor) must reach a file, and a heading of it when it names one;
- a backticked test name `Suite.Test` of a known suite must be a TEST of testbench/ or a ctest
  name of a CMakeLists.txt;
- a backticked repository path (blocks/, pipeline/, testbench/, scripts/, scenes/, traces/,
  rtl_model/, docs/, cmake/, .ci/; with {a,b} alternatives, globs, `x.h/.cc` pairs and stems
  without extension) must exist;
- in docs/scenes.md, a key in the first column of a key table must be a string some reader in
  blocks/, pipeline/ or traces/ spells; and anywhere, the last part of KEY in `--set KEY=VALUE`
  likewise;
- `texsim NAME` in backticks must be a subcommand of `texsim --help` (TEXSIM_BINARY, default
  build/texsim).
Prints every miss as FILE:LINE: what; exit status 1 if any."""
import glob
import os
import re
import subprocess
import sys

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.chdir(root)
docs = sorted(set(glob.glob('docs/**/*.md', recursive=True) + glob.glob('*.md') +
                  glob.glob('traces/*.md') + glob.glob('rtl_model/**/*.md', recursive=True)))
TOP = ('blocks/', 'pipeline/', 'testbench/', 'scripts/', 'scenes/', 'traces/', 'rtl_model/',
       'docs/', 'cmake/', '.ci/')


def read(path):
    with open(path, encoding='utf-8', errors='replace') as f:
        return f.read()


def slug(heading):
    h = heading.strip().lower().replace('`', '')
    h = re.sub(r'[^\w\- ]', '', h)
    return h.replace(' ', '-')


_anchors = {}


def anchors_of(path):
    if path not in _anchors:
        found, seen, code = set(), {}, False
        for line in read(path).splitlines():
            if line.startswith('```'):
                code = not code
            m = None if code else re.match(r'#+\s+(.*)', line)
            if m:
                a = slug(m.group(1))
                k = seen.get(a, 0)
                seen[a] = k + 1
                found.add(a if k == 0 else f'{a}-{k}')
        _anchors[path] = found
    return _anchors[path]


tests = set()
for f in glob.glob('testbench/**/*.cc', recursive=True) + glob.glob('rtl_model/**/*.cc', recursive=True):
    tests.update(re.findall(r'\bTEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)', read(f)))
for f in glob.glob('**/CMakeLists.txt', recursive=True):
    if not f.startswith('build'):
        tests.update(re.findall(r'add_test\(NAME\s+(\w+)\.(\w+)', read(f)))
suites = {s for s, _ in tests}

literals = set()
for pattern in ('blocks/**/*.[hc]*', 'pipeline/**/*.[hc]*', 'traces/**/*.[hc]*'):
    for f in glob.glob(pattern, recursive=True):
        literals.update(re.findall(r'"([a-z_][a-z0-9_]*)"', read(f)))


def path_exists(p):
    p = re.sub(r'[.,:;)]+$', '', p.split('#')[0])
    p = re.sub(r':\d+(-\d+)?$', '', p)
    if '<' in p or 'NAME' in p:  # a placeholder: docs/adding-a-block.md's templates
        return True
    m = re.search(r'\{([^}]*)\}', p)
    if m:
        return all(path_exists(p[:m.start()] + alt + p[m.end():]) for alt in m.group(1).split(','))
    m = re.fullmatch(r'(.*)\.h/\.cc', p)
    if m:
        return path_exists(m.group(1) + '.h') and path_exists(m.group(1) + '.cc')
    if p.endswith('.*'):
        return bool(glob.glob(p[:-2] + '.*'))
    if any(c in p for c in '*?…'):
        return bool(glob.glob(p.replace('…', '*')))
    return os.path.exists(p) or bool(glob.glob(p + '.h') + glob.glob(p + '.cc'))


_subcommands = None


def subcommands():
    global _subcommands
    if _subcommands is None:
        exe = os.environ.get('TEXSIM_BINARY', 'build/texsim')
        out = subprocess.run([exe, '--help'], capture_output=True, text=True, check=False).stdout
        _subcommands, on = set(), False
        for line in out.splitlines():
            on = on or line.startswith('Subcommands:')
            m = re.match(r'\s+([a-z][\w-]*)\s', line)
            if on and m:
                _subcommands.add(m.group(1))
        if not _subcommands:
            sys.exit(f'check_docs: no subcommands in `{exe} --help` (set TEXSIM_BINARY)')
    return _subcommands


def check_line(doc, line, misses, where):
    for m in re.finditer(r'\]\(([^)\s]+)\)', line):
        t = m.group(1)
        if re.match(r'[a-z]+:', t):
            continue
        path, _, anchor = t.partition('#')
        target = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
        if not os.path.exists(target):
            misses.append(f'{where}: link to a missing file: {t}')
        elif anchor and target.endswith('.md') and anchor not in anchors_of(target):
            misses.append(f'{where}: link to a missing heading: {t}')
    for m in re.finditer(r'`([^`]+)`', line):
        c = m.group(1).strip()
        t = re.fullmatch(r'([A-Z]\w+)\.([A-Z]\w+)', c)
        if t and t.group(1) in suites and (t.group(1), t.group(2)) not in tests:
            misses.append(f'{where}: no test {c}')
        if c.startswith(TOP) and ' ' not in c and not path_exists(c):
            misses.append(f'{where}: no file {c}')
        s = re.match(r'texsim ([a-z][\w-]*)', c)
        if s and not re.search(r'[:(]', c) and s.group(1) not in subcommands():  # a message
            misses.append(f'{where}: no subcommand {c}')
        for k in re.findall(r'--set\s+\'?([\w.]+)=', c):
            if not k.isupper() and k.split('.')[-1] not in literals:  # KEY: a placeholder
                misses.append(f'{where}: no scene key {k}')
    if doc == 'docs/scenes.md':
        m = re.match(r'\|\s*((?:`[^`]+`[,/ …]*)+)\|', line)
        for k in re.findall(r'`([^`]+)`', m.group(1)) if m else []:
            if re.fullmatch(r'[a-z_][a-z0-9_]*', k) and k not in literals:
                misses.append(f'{where}: no reader spells the key {k}')


def main():
    misses = []
    for doc in docs:
        code = False
        for n, line in enumerate(read(doc).splitlines(), 1):
            if line.startswith('```'):
                code = not code
                continue
            if not code:
                check_line(doc, line, misses, f'{doc}:{n}')
    for x in misses:
        print(x)
    print(f'check_docs: {len(docs)} files, {len(tests)} tests known, {len(misses)} misses',
          file=sys.stderr)
    return 1 if misses else 0


if __name__ == '__main__':
    sys.exit(main())

#!/usr/bin/env python3
"""check_layers.py — the modules' layering: every dependency points down.

usage: tools/check_layers.py [--objects DIR] [ROOT]

ROOT (default .) is a strata checkout. The modules are the folders of src/, in
the layers below, lowest first; include/st_*.h belong to the modules listed in
HEADERS; the kernels (kernels/<folder>/) are below every module, their folders
in layers of their own (KERNEL_LAYERS). It checks:

  1. the Makefile's MODULES are the folders of src/, in the order of LAYERS
     (so a new folder has to be given its place here first), its KERNEL_DIRS
     the folders of kernels/ in the order of KERNEL_LAYERS, and no source,
     kernel or test lies outside the folders the build and `make test` read
     (src/<module>/, kernels/<folder>/, tests/<layer>/);
  2. every quoted #include of src/, include/ and kernels/ names one file, found
     as the compiler finds it (the including file's folder, include/, the
     module folders, the kernel folders) and by no other name in those
     folders;
  3. a file includes only its own module's headers, the kernels' and those of
     modules in lower layers; a module's private header (src/<module>/*.h) only
     from its own module; a kernel file only kernel files of its own folder
     or of a folder below it;
  4. with --objects DIR (the build's obj/ folder, DIR/<module>/<file>.o): the
     same for the symbols each object uses from another (nm), and no circle of
     files that call each other (a calls b calls ... calls a), inside a module
     or across modules.

Prints one line per fault, "check_layers: FILE: what", and exits 1 if any.
Standard library and binutils' nm only.
"""
import os
import re
import subprocess
import sys

# Lowest first; modules in one layer may not use each other.
LAYERS = [
    ["base"],
    ["image"],
    ["device", "sampling", "filter", "bvh"],
    ["scene"],
    ["render"],
    ["lab"],
    ["cli"],
]

# The kernels' folders, lowest first: a kernel file includes files of its own
# folder and of the folders before it. The traversal (geom) knows nothing of
# shading; the integrator draws samples and traces rays; the film is last, as
# the stages run (adaptive sampling's moments are the film's).
KERNEL_LAYERS = ["shared", "sample", "geom", "integrator", "film"]

# The public headers (include/) of each module.
HEADERS = {
    "base": ["st_error.h", "st_names.h", "st_outfile.h", "st_version.h", "st_embedded.h"],
    "image": ["st_image.h", "st_tonemap.h", "st_diff.h", "st_film.h"],
    "device": ["st_device.h"],
    "sampling": ["st_sampling.h"],
    "filter": ["st_filter.h"],
    "bvh": ["st_bvh.h"],
    "scene": ["st_scene.h", "st_lights.h"],
    "render": ["st_render.h", "st_envmap.h", "st_mem_plan.h", "st_trace_bench.h"],
    "lab": ["st_signal.h", "st_plot.h", "st_sheet.h"],
}

KERNELS = "kernels"
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
SOURCE = (".c", ".h", ".cpp", ".cl")

faults = []


def fault(path, what):
    faults.append("check_layers: %s: %s" % (path, what))


def level_of():
    level = {KERNELS: -1}
    for i, layer in enumerate(LAYERS):
        for m in layer:
            level[m] = i
    return level


def makefile_list(root, name):
    text = open(os.path.join(root, "Makefile"), encoding="utf-8").read()
    m = re.search(r"^%s\s*:=\s*(.*)$" % name, text, re.M)
    return m.group(1).split() if m else None


def listdir(path):
    return sorted(os.listdir(path)) if os.path.isdir(path) else []


def check_modules(root):
    modules = [m for layer in LAYERS for m in layer]
    folders = [d for d in listdir(os.path.join(root, "src"))
               if os.path.isdir(os.path.join(root, "src", d))]
    if sorted(folders) != sorted(modules):
        fault("src", "folders %s, but the layers name %s" % (folders, modules))
    if makefile_list(root, "MODULES") != modules:
        fault("Makefile", "MODULES %s, not the layers' order %s" % (makefile_list(root, "MODULES"), modules))
    kfolders = [d for d in listdir(os.path.join(root, KERNELS))
                if os.path.isdir(os.path.join(root, KERNELS, d))]
    if sorted(kfolders) != sorted(KERNEL_LAYERS):
        fault(KERNELS, "folders %s, but the kernel layers name %s" % (kfolders, KERNEL_LAYERS))
    if makefile_list(root, "KERNEL_DIRS") != KERNEL_LAYERS:
        fault("Makefile", "KERNEL_DIRS %s, not the kernel layers' order %s" %
              (makefile_list(root, "KERNEL_DIRS"), KERNEL_LAYERS))
    stray = [("src", SOURCE + (".cpp",), "src/<module>/, where the build looks"),
             (KERNELS, (".cl", ".h"), "kernels/<folder>/, where the build looks"),
             ("tests", ("",), "tests/<layer>/, where make test looks")]
    for folder, ends, where in stray:
        for name in listdir(os.path.join(root, folder)):
            rel = os.path.join(folder, name)
            if os.path.isfile(os.path.join(root, rel)) and name.endswith(ends) and \
                    (folder != "tests" or name.startswith("test_")):
                fault(rel, "outside %s" % where)
    return modules


def search_path(root, modules):
    """The folders the compiler searches after the includer's own, in order, with their module."""
    kdirs = [d for d in listdir(os.path.join(root, KERNELS))
             if os.path.isdir(os.path.join(root, KERNELS, d))]
    path = [("include", None)]
    path += [(os.path.join("src", m), m) for m in modules]
    path += [(os.path.join(KERNELS, d), KERNELS) for d in kdirs]
    return path


def owner_table(root, path):
    """Every header's module, by file name; a name in two folders is a fault."""
    header_module = {h: m for m, hs in HEADERS.items() for h in hs}
    owner, where = {}, {}
    for folder, module in path:
        for name in listdir(os.path.join(root, folder)):
            if not name.endswith((".h", ".cl")):
                continue
            rel = os.path.join(folder, name)
            if name in where:
                fault(rel, "the same name as %s: an include of it is ambiguous" % where[name])
                continue
            where[name] = rel
            if folder == "include":
                module = header_module.get(name)
                if module is None:
                    fault(rel, "a public header of no module (add it to HEADERS in tools/check_layers.py)")
                    continue
            owner[rel] = module
    for m, hs in HEADERS.items():
        for h in hs:
            if os.path.join("include", h) not in where.values():
                fault("tools/check_layers.py", "HEADERS names include/%s, which does not exist" % h)
    return owner


def module_of(rel):
    parts = rel.split(os.sep)
    if parts[0] == "src" and len(parts) > 2:
        return parts[1]
    if parts[0] == KERNELS:
        return KERNELS
    return None


def kernel_level(rel):
    """A kernel file's place in KERNEL_LAYERS (its folder's), or None."""
    parts = rel.split(os.sep)
    if parts[0] == KERNELS and len(parts) > 2 and parts[1] in KERNEL_LAYERS:
        return KERNEL_LAYERS.index(parts[1])
    return None


def may_use(user, used, level, private):
    """Whether a file of module `user` may depend on module `used` (private: a src/ header)."""
    if used == user:
        return True
    if user == KERNELS:
        return False
    if private and used != KERNELS:
        return False
    return level[used] < level[user]


def check_includes(root, modules, path, owner, level):
    files = []
    for folder, _ in path:
        if folder == "include":
            files += [os.path.join(folder, f) for f in listdir(os.path.join(root, folder))]
    for m in modules:
        files += [os.path.join("src", m, f) for f in listdir(os.path.join(root, "src", m))]
    for d in listdir(os.path.join(root, KERNELS)):
        files += [os.path.join(KERNELS, d, f) for f in listdir(os.path.join(root, KERNELS, d))]
    for rel in files:
        if not rel.endswith(SOURCE):
            continue
        user = owner.get(rel) or module_of(rel)
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            for lineno, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                name = m.group(1)
                own = os.path.join(os.path.dirname(rel), name)
                found = own if os.path.isfile(os.path.join(root, own)) else None
                for folder, _ in path:
                    cand = os.path.join(folder, name)
                    if found is None and os.path.isfile(os.path.join(root, cand)):
                        found = cand
                where = "%s:%d" % (rel, lineno)
                if found is None:
                    fault(where, '"%s" is in none of the include folders' % name)
                    continue
                used = owner.get(found, module_of(found))
                private = found.startswith("src" + os.sep)
                if user is None or used is None:
                    continue
                if not may_use(user, used, level, private):
                    fault(where, 'includes %s of module %s, %s' % (found, used, why(user, used, level, private)))
                elif user == KERNELS and used == KERNELS:
                    a, b = kernel_level(rel), kernel_level(found)
                    if a is not None and b is not None and b > a:
                        fault(where, 'includes %s, of kernels/%s/, above kernels/%s/ '
                              '(a kernel file includes only its own folder and those below)'
                              % (found, KERNEL_LAYERS[b], KERNEL_LAYERS[a]))


def why(user, used, level, private):
    if user == KERNELS:
        return "and a kernel file may include only kernel files"
    if private and level[used] < level[user]:
        return "a private header of another module"
    if level[used] == level[user]:
        return "in the same layer as %s (modules of one layer do not use each other)" % user
    return "above %s" % user


def symbols(obj):
    out = subprocess.run(["nm", obj], capture_output=True, text=True, check=True).stdout
    defined, undefined = set(), set()
    for line in out.splitlines():
        p = line.split()
        if len(p) == 3 and p[1] in "TDBRCGSVW":
            defined.add(p[2])
        elif len(p) == 2 and p[0] == "U":
            undefined.add(p[1])
    return defined, undefined


def check_objects(objdir, level):
    defs, uses = {}, {}
    for m in sorted(level):
        for f in listdir(os.path.join(objdir, m)):
            if f.endswith(".o"):
                rel = os.path.join(m, f)
                d, u = symbols(os.path.join(objdir, rel))
                uses[rel] = u
                for s in d:
                    defs[s] = rel
    if not uses:
        fault(objdir, "no objects to check (build first)")
        return
    graph = {f: sorted({defs[s] for s in u if s in defs and defs[s] != f}) for f, u in uses.items()}
    for f, to in sorted(graph.items()):
        for t in to:
            user, used = f.split(os.sep)[0], t.split(os.sep)[0]
            if not may_use(user, used, level, False):
                names = sorted(s for s in uses[f] if defs.get(s) == t)[:3]
                fault("src/%s" % f[:-2], "calls %s (%s) of module %s, %s" %
                      (t[:-2], ", ".join(names), used, why(user, used, level, False)))
    for circle in circles(graph):
        fault("src/%s" % circle[0][:-2], "a circle of files calling each other: %s" %
              " -> ".join(c[:-2] for c in circle + [circle[0]]))


def circles(graph):
    """One cycle through each strongly connected component of more than one file (Tarjan)."""
    index, low, stack, on, found = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, []):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(cycle_in(sorted(comp), graph))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def cycle_in(comp, graph):
    """A cycle through comp[0] inside the component (breadth-first back to it)."""
    inside, start = set(comp), comp[0]
    prev, frontier = {start: None}, [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in graph.get(v, []):
                if w == start:
                    path = [v]
                    while prev[path[-1]] is not None:
                        path.append(prev[path[-1]])
                    return path[::-1]
                if w in inside and w not in prev:
                    prev[w] = v
                    nxt.append(w)
        frontier = nxt
    return comp


def main(argv):
    objdir, args = None, argv[1:]
    if args[:1] == ["--objects"]:
        objdir, args = args[1], args[2:]
    root = args[0] if args else "."
    level = level_of()
    modules = check_modules(root)
    path = search_path(root, modules)
    owner = owner_table(root, path)
    check_includes(root, modules, path, owner, level)
    if objdir:
        check_objects(objdir, level)
    for line in faults:
        print(line)
    return 1 if faults else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

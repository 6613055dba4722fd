"""Shared selection for the reach-set assemblers (assemble-set2.py, -set3.py, -set4.py).
Named reach_select, not select: a select.py beside the scripts would shadow the standard
module that subprocess imports.

From bare git mirrors (the fetch tool: /work/.mirror/OWNER+NAME/repo, or .../repo/.git),
copies each chosen mesh file of HEAD plus the files a .gltf names (buffers, images), and
writes OUT/MANIFEST.tsv (file kind source path bytes repo commit licence). Per source: the
sorted paths matching `include` (and not `exclude`), every k-th when more than `cap`
(k = ceil(n/cap)). Skipped: files over `max_bytes`, blobs absent from the snapshot, Git LFS
pointers, and (dedup) a blob already taken (same git hash)."""
import collections, json, math, os, re, subprocess

MIRRORS = "/work/.mirror"


class Source:
    def __init__(self, repo, short, licence, include, exclude=None, cap=None):
        self.repo, self.short, self.licence = repo, short, licence
        self.include, self.exclude, self.cap = include, exclude, cap


def git_dir(repo):
    base = f"{MIRRORS}/{repo.replace('/', '+')}/repo"
    return base + "/.git" if os.path.isdir(base + "/.git") else base


def git(repo, *args, text=True):
    return subprocess.run(["git", "--git-dir", git_dir(repo), *args],
                          capture_output=True, text=text, check=True).stdout


def gltf_dependencies(data):
    """The relative URIs of a .gltf's buffers and images (none when it is not valid JSON)."""
    try: doc = json.loads(data)
    except ValueError: return []
    if not isinstance(doc, dict): return []
    items = []
    for key in ("buffers", "images"):  # lists in glTF 2.0, objects keyed by id in 1.0
        group = doc.get(key) or []
        items += list(group.values()) if isinstance(group, dict) else group if isinstance(group, list) else []
    uris = [item.get("uri", "") for item in items if isinstance(item, dict)]
    return [u for u in uris if isinstance(u, str) and u and not u.startswith("data:")]


def assemble(sources, out, max_bytes, dedup=False, ignore_case=False):
    """Copies the selection into `out`, writes its MANIFEST.tsv and returns the rows."""
    rows, seen = [], set()
    flags = re.I if ignore_case else 0
    for s in sources:
        commit = git(s.repo, "rev-parse", "HEAD").strip()
        sizes, blobs = {}, {}
        for line in git(s.repo, "ls-tree", "-r", "-l", "HEAD").splitlines():
            meta, path = line.split("\t", 1)
            _, _, blob, size = meta.split()
            sizes[path] = int(size) if size.isdigit() else None
            blobs[path] = blob

        def copy(path):
            data = git(s.repo, "show", f"HEAD:{path}", text=False)
            dst = f"{out}/{s.short}/{path}"
            os.makedirs(os.path.dirname(dst), exist_ok=True)
            open(dst, "wb").write(data)
            return data

        chosen = [p for p in sorted(sizes) if re.search(s.include, p, flags)
                  and not (s.exclude and re.search(s.exclude, p, flags))]
        k = math.ceil(len(chosen) / s.cap) if s.cap else 1
        for path in chosen[::max(k, 1)]:
            size = sizes[path]
            if size is None or size > max_bytes or (dedup and blobs[path] in seen): continue
            try: data = copy(path)
            except subprocess.CalledProcessError: continue  # absent from the snapshot
            if data.startswith(b"version https://git-lfs"):
                os.remove(f"{out}/{s.short}/{path}")
                continue
            seen.add(blobs[path])
            if path.endswith(".gltf"):
                for uri in gltf_dependencies(data):
                    dep = os.path.normpath(os.path.join(os.path.dirname(path), uri.replace("%20", " ")))
                    if sizes.get(dep): copy(dep)
            first, _, rest = path.partition("/")
            if not rest:  # a file at the repository's top: source ".", so kind/./name is it
                first, rest = ".", path
            rows.append([f"{s.short}/{path}", s.short, first, rest, str(len(data)), s.repo, commit, s.licence])
    os.makedirs(out, exist_ok=True)
    with open(f"{out}/MANIFEST.tsv", "w") as f:
        f.write("file\tkind\tsource\tpath\tbytes\trepo\tcommit\tlicence\n")
        for r in rows: f.write("\t".join(r) + "\n")
    print(len(rows), collections.Counter(r[1] for r in rows))
    return rows

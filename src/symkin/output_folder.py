"""The one writer of output folders: no symlinks followed, no foreign file deleted, no mix.

Every file symkin writes for a user (``derive``, ``generate``, ``latex``, the extension build)
goes through :func:`write_folder`.  Its rules (docs/security.md):

* **Nothing is written through a symbolic link.**  The output folder itself and every folder
  on the way to a file must be real folders inside it; a symlink there is an error.  A symlink
  at a file's own place is replaced by the file (``os.replace`` renames onto the link itself),
  so its target is never touched.
* **A manifest** (``.symkin-files``, or ``.<name>.symkin-files`` for a document) lists what the
  run wrote.  A later run deletes only files that its manifest lists and that the new run no
  longer produces; a file symkin did not write is never deleted.
* **Complete or untouched.**  Everything is first written into a fresh sibling folder (the
  slow part: rendering and compiling happen there).  When the output folder holds nothing but
  files of the previous manifest, the two folders are swapped by renames, so an interrupted
  run leaves either the old folder or the new one.  When the user keeps files of their own in
  the folder, the new files are renamed in one by one; the manifest is marked incomplete
  first and completed last, so an interrupted run is visible (``generate --check`` and the
  next run report it).
"""

from __future__ import annotations

import os
import secrets
import shutil
import stat
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path, PurePosixPath

from symkin.errors import SymkinError

MANIFEST_SUFFIX = "symkin-files"
MANIFEST_HEADER = "# files written by symkin; a later run deletes only files listed here"
INCOMPLETE = "# incomplete: a run stopped while writing; rerun the command"


def manifest_name(document: str | None = None) -> str:
    """``.symkin-files`` for a folder of one output, ``.<document>.symkin-files`` for one
    document among others (LaTeX files beside a user's notes)."""
    return f".{document}.{MANIFEST_SUFFIX}" if document else f".{MANIFEST_SUFFIX}"


def manifest_text(relatives: Iterable[str]) -> str:
    """The manifest's content: a header and the relative paths, sorted (deterministic)."""
    return "\n".join([MANIFEST_HEADER, *sorted(relatives)]) + "\n"


def read_manifest(root: Path, name: str) -> tuple[frozenset[str], bool]:
    """The relative paths a manifest lists, and whether it says the run completed."""
    path = root / name
    if path.is_symlink() or not path.is_file():
        return frozenset(), True
    lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    # A manifest may come with a checkout or an archive: a line that leaves the folder
    # (absolute, "..") is never taken as ours, so it can never be deleted or compared.
    listed = frozenset(
        line for line in lines if line and not line.startswith("#") and _is_plain(line)
    )
    return listed, INCOMPLETE not in lines


def _is_plain(relative: str) -> bool:
    try:
        check_relative(relative)
    except SymkinError:
        return False
    return True


def check_relative(relative: str) -> PurePosixPath:
    """A generated file's path: relative, no ``..``, no empty parts."""
    path = PurePosixPath(relative)
    if path.is_absolute() or not path.parts or any(p in ("", ".", "..") for p in path.parts):
        raise SymkinError(f"refusing to write {relative!r}: not a plain relative path")
    return path


def check_no_symlink(root: Path, relative: PurePosixPath) -> None:
    """Raise when ``root`` or a folder between it and ``relative`` is a symbolic link."""
    folder = root
    for part in (None, *relative.parts[:-1]):
        if part is not None:
            folder = folder / part
        if folder.is_symlink():
            raise SymkinError(
                f"refusing to write into {folder}: it is a symbolic link "
                "(symkin never writes through links; remove it or choose another folder)"
            )
        if folder.exists() and not folder.is_dir():
            raise SymkinError(f"cannot write into {folder}: it is a file, not a folder")


def check_output_root(root: Path) -> None:
    """Refuse the file system's root as an output folder: a run would scatter its files
    there (and, as root, among the system's own), and there is no sibling to stage in."""
    resolved = root.resolve()
    if resolved == resolved.parent:
        raise SymkinError(
            f"refusing to write into {root}: it is the file system's root; choose a folder"
        )


def _check_regular(target: Path) -> None:
    """Refuse to replace a device, a pipe or a socket, or a link to one (``/dev/null``,
    ``/dev/stdout``): symkin writes regular files, and renaming over such a node would put a
    plain file in its place."""
    try:
        mode = target.lstat().st_mode
        # /dev/stdout -> /proc/self/fd/1 ends at whatever stdout is, a regular file when
        # redirected: a chain through the system's device or process tree counts as a device.
        if stat.S_ISLNK(mode) and not _through_devices(target):
            mode = target.stat().st_mode
    except OSError:  # nothing there, or a dangling link: replaced by the file, as any link
        return
    if stat.S_ISLNK(mode) or not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise SymkinError(
            f"refusing to write {target}: it is a device, pipe or socket (or a link to one), "
            "not a regular file; give a file name"
        )


def _through_devices(link: Path, hops: int = 40) -> bool:
    """Whether the chain of links from ``link`` passes through ``/dev`` or ``/proc``."""
    path = link
    for _ in range(hops):
        if not path.is_symlink():
            return False
        path = Path(os.path.normpath(path.parent / os.readlink(path)))  # "../../proc/..." too
        if path.parts[1:2] in (("dev",), ("proc",)) and path.is_absolute():
            return True
    return True  # a loop of links: nothing a file should replace


def _write_new(path: Path, content: str | bytes) -> None:
    """Create ``path`` (which must not exist: O_EXCL, so no link is followed)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    data = content.encode("utf-8") if isinstance(content, str) else content
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
    with os.fdopen(descriptor, "wb") as handle:
        handle.write(data)


def _replace_file(source: Path, root: Path, relative: str) -> None:
    """Rename ``source`` onto ``root/relative``; a link at the target is replaced, not followed."""
    check_no_symlink(root, PurePosixPath(relative))
    target = root / relative
    target.parent.mkdir(parents=True, exist_ok=True)
    if target.is_dir() and not target.is_symlink():
        raise SymkinError(f"cannot write {target}: a folder of that name is in the way")
    _check_regular(target)
    os.replace(source, target)


def _files_under(root: Path) -> set[str]:
    """Relative paths of every file and link under ``root``, links not followed."""
    found = set()
    for folder, directories, files in os.walk(root, followlinks=False):
        base = Path(folder)
        links = [d for d in directories if (base / d).is_symlink()]
        for name in [*files, *links]:
            found.add((base / name).relative_to(root).as_posix())
        if not files and not directories and base != root:
            found.add(base.relative_to(root).as_posix() + "/")  # an empty folder of the user's
    return found


def _other_manifests(root: Path, own: str) -> frozenset[str]:
    """Files listed by the other outputs' manifests in the same folder (kept)."""
    listed: set[str] = set()
    for path in root.glob(f".*{MANIFEST_SUFFIX}"):
        if path.name != own:
            listed |= read_manifest(root, path.name)[0]
    return frozenset(listed)


def _holds_cwd(root: Path) -> bool:
    cwd = Path.cwd().resolve()
    resolved = root.resolve()
    return cwd == resolved or resolved in cwd.parents


def write_folder(
    root: Path | str,
    files: Mapping[str, str | bytes],
    *,
    document: str | None = None,
    finish: Callable[[Path], Iterable[str]] | None = None,
) -> list[str]:
    """Write ``{relative path: text}`` under ``root`` by the rules above.

    ``finish(staging)`` runs after the files are in the staging folder (the extension build)
    and returns the relative paths of what it added there; they join the manifest.  Returns
    the relative paths written.  A file-system error is a :class:`SymkinError` naming the path.
    """
    root = Path(root)
    relatives = {check_relative(r).as_posix(): text for r, text in files.items()}
    own = manifest_name(document)
    check_output_root(root)
    check_no_symlink(root, PurePosixPath("x"))
    parent = root.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        staging = _sibling(root, "new")
    except OSError as error:
        raise SymkinError(f"cannot write {root}: {error.strerror or error}") from None
    try:
        for relative, text in relatives.items():
            _write_new(staging / relative, text)
        written = sorted({*relatives, *(finish(staging) if finish else ())})
        _write_new(staging / own, manifest_text(written))
        _commit(root, staging, own, written)
    except OSError as error:
        raise SymkinError(
            f"cannot write {error.filename or root}: {error.strerror or error}"
        ) from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return written


def _commit(root: Path, staging: Path, own: str, written: list[str]) -> None:
    previous, _ = read_manifest(root, own)
    present = _files_under(root) if root.exists() else set()
    ours_only = present <= previous | {own}
    if ours_only and not _holds_cwd(root):
        _swap(root, staging)
        return
    keep = _other_manifests(root, own) | set(written)
    _write_manifest(root, manifest_text(sorted(previous | set(written))) + INCOMPLETE + "\n", own)
    for relative in written:
        _replace_file(staging / relative, root, relative)
    for relative in sorted(previous - keep):
        stale = root / relative
        check_no_symlink(root, PurePosixPath(relative))
        inside = stale.parent.resolve().is_relative_to(root.resolve())
        if inside and (stale.is_symlink() or stale.is_file()):
            stale.unlink()
            _remove_empty_folders(root, stale.parent)
    _write_manifest(root, manifest_text(written), own)


def replace_file(root: Path, relative: str, content: str | bytes) -> Path:
    """Write one file that no manifest tracks (a PDF and its log beside the document): to a
    temporary name, then renamed into place, never through a link."""
    check_relative(relative)
    check_no_symlink(root, PurePosixPath(relative))
    target = root / relative
    temporary = target.with_name(f".{target.name}.symkin-{secrets.token_hex(4)}")
    try:
        _write_new(temporary, content)
        _replace_file(temporary, root, relative)
    except OSError as error:
        raise SymkinError(f"cannot write {target}: {error.strerror or error}") from None
    finally:
        temporary.unlink(missing_ok=True)
    return target


def _remove_empty_folders(root: Path, folder: Path) -> None:
    """Remove ``folder`` and its parents below ``root`` while they are empty (our deletions
    emptied them; a folder with anything in it stays)."""
    while folder != root and root in folder.parents:
        try:
            folder.rmdir()
        except OSError:
            return
        folder = folder.parent


def _write_manifest(root: Path, text: str, own: str) -> None:
    temporary = root / f"{own}.new"
    if temporary.is_symlink() or temporary.exists():
        temporary.unlink()
    _write_new(temporary, text)
    os.replace(temporary, root / own)


def _swap(root: Path, staging: Path) -> None:
    """Replace ``root`` (absent, or holding only our files) by ``staging`` with renames."""
    if not root.exists():
        os.rename(staging, root)
        staging.mkdir()  # the caller removes it
        return
    old = _sibling(root, "old")
    os.rename(root, old / "tree")
    try:
        os.rename(staging, root)
    except BaseException:
        # Ctrl-C, the time limit or an error between the renames: put the old folder back.
        os.rename(old / "tree", root)
        old.rmdir()
        raise
    staging.mkdir()
    shutil.rmtree(old, ignore_errors=True)


def _sibling(root: Path, what: str) -> Path:
    """A new hidden folder beside ``root`` (same file system, so renames are atomic); made
    with ``mkdir``, so it gets the user's umask like any folder they create."""
    while True:
        folder = root.parent / f".{root.name}.symkin-{what}-{secrets.token_hex(4)}"
        try:
            folder.mkdir()
            return folder
        except FileExistsError:
            continue

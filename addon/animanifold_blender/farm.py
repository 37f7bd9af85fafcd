"""Render-farm entry points: a chunk of frames baked by one task, then the chunks assembled.

Called in a Blender that has the scene open, from any install of the add-on (legacy,
4.2+ extension — module_alias makes the name work — or a folder on PYTHONPATH)::

    blender -b scene.blend --python-exit-code 1 --python-expr \\
        "from animanifold_blender import farm; farm.main()" -- bake-chunk --start 1 --end 50 --directory //farm/
    blender -b scene.blend --python-exit-code 1 --python-expr \\
        "from animanifold_blender import farm; farm.main()" -- assemble --directory //farm/

or as functions: ``farm.bake_chunk(1, 50, directory="//farm/", outputs="blend,obj")``,
``farm.assemble(directory="//farm/")``. farm/openjd/bake/template.yaml runs these.

A chunk task only reads the .blend and its .amf cache and writes its own files (the
frames' OBJ/PLY, `<object>_<first>-<last>.blend|.abc|.mtl`, and last its manifest
`<object>_<first>-<last>.done.json`), each atomically (farm_files); a task whose manifest
still matches its files skips its work. Assemble links every chunk's frame objects into one
collection played by one node group, saves that .blend and exports one Alembic of the whole
range. Nothing is saved into the opened .blend.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import math
import os
import re
import sys

import bpy

from . import bake, cache_follow, farm_files
from .object_manifold import manifold_for, shown_manifold
from .reporting import ReportedError

OUTPUTS = ("blend", "abc", "obj", "ply")
MANIFEST_FORMAT = 1


class FarmError(ReportedError):
    """A farm task that cannot run as asked (the message names the object, frame or file)."""


@contextlib.contextmanager
def _addon_registered():
    """The add-on registered for the task: already when Blender enabled it, else (a folder
    on PYTHONPATH) registered here and unregistered after (bpy as a module hangs at exit
    with classes registered)."""
    if hasattr(bpy.types, "ANIMANIFOLD_OT_bake"):
        yield
        return
    package = importlib.import_module(__package__)
    package.register()
    try:
        yield
    finally:
        package.unregister()


def _parse_outputs(outputs) -> list[str]:
    items = outputs.split(",") if isinstance(outputs, str) else list(outputs)
    items = sorted({o.strip().lower() for o in items if o.strip()})
    unknown = [o for o in items if o not in OUTPUTS]
    if unknown or not items:
        raise FarmError(f"unknown farm outputs {unknown or items}: choose from {', '.join(OUTPUTS)}")
    return items


def manifold_objects(name: str | None = None) -> list:
    """The scene's manifold objects, or the one named `name` (a FarmError names what exists)."""
    found = [o for o in bpy.context.scene.objects if o.animanifold.is_manifold]
    if name:
        chosen = [o for o in found if o.name == name]
        if not chosen:
            raise FarmError(f"no manifold object '{name}' in {bpy.data.filepath or 'the scene'} "
                            f"(manifold objects: {[o.name for o in found]})")
        return chosen
    if not found:
        raise FarmError(f"{bpy.data.filepath or 'the scene'} has no manifold object to bake")
    return found


def _folder(directory: str) -> str:
    if directory.startswith("//") and not bpy.data.filepath:
        raise FarmError(f"the farm folder '{directory}' is relative to a .blend that is not saved")
    folder = bpy.path.abspath(directory)
    os.makedirs(folder, exist_ok=True)
    return folder


def range_suffix(first: int, last: int) -> str:
    return f"_{first:06d}-{last:06d}"


def chunk_tag(obj, first: int, last: int) -> str:
    """The stem of a chunk's own files: <object>_<first>-<last>."""
    return bpy.path.clean_name(obj.name) + range_suffix(first, last)


def _frames_of(obj, start: int, end: int) -> list[int]:
    manifold_for(obj)  # validates the cache first: its error names the object and file
    t0, t1 = shown_manifold(obj).time_range
    first, last = max(start, math.ceil(t0 - 1e-9)), min(end, math.floor(t1 + 1e-9))
    return list(range(first, last + 1))


def _chunk_files(obj, frames: list[int], outputs: list[str]) -> list[str]:
    """Every file name the chunk writes (their stale temporaries are removed before a re-run)."""
    tag = chunk_tag(obj, frames[0], frames[-1])
    names = [f"{tag}.{o}" for o in ("blend", "abc") if o in outputs]
    for fmt in ("OBJ", "PLY"):
        if fmt.lower() in outputs:
            names += [bake.frame_file_name(obj, f, fmt) for f in frames]
    if "obj" in outputs:
        names.append(bake.mtl_file_name(obj, range_suffix(frames[0], frames[-1])))
    return names + [tag + ".done.json"]


def _bake_object_chunk(obj, frames: list[int], folder: str, outputs: list[str]) -> str:
    first, last = frames[0], frames[-1]
    tag = chunk_tag(obj, first, last)
    manifest = os.path.join(folder, tag + ".done.json")
    description = {"format": MANIFEST_FORMAT, "object": obj.name, "first": first, "last": last, "outputs": outputs}
    if farm_files.completed(manifest, description):
        return f"'{obj.name}' frames {first}–{last}: complete already ({os.path.basename(manifest)}), skipped"
    farm_files.remove_stale(folder, _chunk_files(obj, frames, outputs))
    files = []
    for fmt in ("OBJ", "PLY"):
        if fmt.lower() in outputs:
            files += bake.export_sequence(obj, frames, folder, fmt, write=farm_files.write_bytes,
                                          mtl_suffix=range_suffix(first, last))
    if "blend" in outputs or "abc" in outputs:
        transaction = bake.NodeGroupBake(obj)
        try:
            transaction.apply(frames)
        except BaseException:
            transaction.rollback()
            raise
        transaction.commit()
        files += _save_baked(obj, folder, tag, first, last, outputs)
    farm_files.write_manifest(manifest, description, files)
    return f"'{obj.name}' frames {first}–{last}: {len(files)} files in {folder}"


def _save_baked(obj, folder: str, stem: str, first: int, last: int, outputs) -> list[str]:
    """The node-group bake now on `obj` as `<stem>.abc` (Blender's exporter) and/or a copy of
    the .blend `<stem>.blend`, each written atomically."""
    written = []
    if "abc" in outputs:
        path = os.path.join(folder, stem + ".abc")
        farm_files.write_with(path, lambda tmp: bake.export_alembic(bpy.context, obj, tmp, first, last))
        written.append(path)
    if "blend" in outputs:
        path = os.path.join(folder, stem + ".blend")
        farm_files.write_with(path, _save_copy)
        written.append(path)
    return written


def bake_chunk(start: int, end: int, directory: str = "//animanifold_farm/", object: str | None = None,
               outputs="blend,obj") -> list[str]:
    """Bakes frames start..end (clipped to each manifold's frames) of the named manifold object,
    or of every one, into `directory` (see the module); one line per object."""
    if end < start:
        raise FarmError(f"the chunk's frames {start}–{end} are empty (end before start)")
    wanted = _parse_outputs(outputs)
    with _addon_registered():
        folder = _folder(directory)
        notes = []
        for obj in manifold_objects(object):
            frames = _frames_of(obj, start, end)
            if not frames:
                notes.append(f"'{obj.name}': no frames in {start}–{end}")
                continue
            notes.append(_bake_object_chunk(obj, frames, folder, wanted))
    for note in notes:
        print(f"animanifold farm: {note}")
    return notes


# -- assemble ------------------------------------------------------------------------

def _chunks(obj, folder: str) -> list[dict]:
    """The complete chunks of `obj` in `folder` (their manifests), in frame order; a FarmError
    when none is there, one is damaged, or frames are missing between two."""
    pattern = re.compile(re.escape(bpy.path.clean_name(obj.name)) + r"_(-?\d+)-(-?\d+)\.done\.json$")
    chunks = []
    for name in sorted(os.listdir(folder)):
        if not pattern.match(name):
            continue
        entry = farm_files.read_manifest(os.path.join(folder, name))
        if entry is None or entry.get("object") != obj.name:
            continue
        keys = ("format", "object", "first", "last", "outputs")
        if not farm_files.completed(os.path.join(folder, name), {k: entry.get(k) for k in keys}):
            raise FarmError(f"chunk {name} of '{obj.name}' lists files that are missing or changed: re-run its task")
        chunks.append(dict(entry, manifest=name))
    if not chunks:
        raise FarmError(f"no baked chunk of '{obj.name}' in {folder}: run the bake-chunk tasks first")
    chunks.sort(key=lambda c: c["first"])
    for a, b in zip(chunks, chunks[1:]):
        if b["first"] != a["last"] + 1:
            raise FarmError(f"'{obj.name}': frames {a['last'] + 1}–{b['first'] - 1} are in no chunk (or chunks "
                            f"overlap) between {a['manifest']} and {b['manifest']}")
    return chunks


def _link_chunk_frames(obj, folder: str, chunks: list[dict]):
    """A new collection holding every chunk's frame objects, linked from the chunk .blends,
    in frame order."""
    collection = bpy.data.collections.new(f"{obj.name}_bake.new")
    for chunk in chunks:
        path = os.path.join(folder, f"{chunk_tag(obj, chunk['first'], chunk['last'])}.blend")
        if "blend" not in chunk["outputs"]:
            raise FarmError(f"chunk {chunk['manifest']} has no .blend (bake it with the 'blend' output)")
        name = f"{obj.name}_bake"
        with bpy.data.libraries.load(path, link=True, relative=True) as (source, target):
            if name not in source.collections:
                raise FarmError(f"{path} holds no collection '{name}' (collections: {list(source.collections)})")
            target.collections = [name]
        linked = {o.name: o for o in target.collections[0].objects}
        for frame in range(chunk["first"], chunk["last"] + 1):
            frame_obj = linked.get(bake.frame_object_name(obj.name, frame))
            if frame_obj is None:
                raise FarmError(f"{path} has no object for frame {frame} of '{obj.name}'")
            collection.objects.link(frame_obj)
    return collection


def assemble(directory: str = "//animanifold_farm/", object: str | None = None, outputs="blend,abc",
             blend_name: str = "assembled.blend") -> list[str]:
    """Plays every chunk of each manifold object (or the named one) through one node group
    and writes `<object>.abc` of the whole range and/or `blend_name`, in `directory`."""
    wanted = _parse_outputs(outputs)
    with _addon_registered():
        folder = _folder(directory)
        notes = []
        for obj in manifold_objects(object):
            chunks = _chunks(obj, folder)
            first, last = chunks[0]["first"], chunks[-1]["last"]
            collection = _link_chunk_frames(obj, folder, chunks)
            transaction = bake.NodeGroupBake(obj)
            transaction.apply(list(range(first, last + 1)), collection=collection)
            transaction.commit()
            if "abc" in wanted:
                _save_baked(obj, folder, bpy.path.clean_name(obj.name), first, last, ("abc",))
            notes.append(f"'{obj.name}': {len(chunks)} chunks, frames {first}–{last}")
        if "blend" in wanted:
            path = os.path.join(folder, blend_name)
            farm_files.write_with(path, _save_copy)
            notes.append(f"saved {path}")
    for note in notes:
        print(f"animanifold farm: {note}")
    return notes


# -- command line (the arguments after Blender's `--`) ---------------------------------

def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="animanifold_blender.farm", description="render-farm tasks in Blender")
    commands = parser.add_subparsers(dest="command", required=True)
    chunk = commands.add_parser("bake-chunk", help="bake one chunk of frames")
    chunk.add_argument("--start", type=int, required=True)
    chunk.add_argument("--end", type=int, required=True, help="last frame of the job (or of the chunk)")
    chunk.add_argument("--chunk-size", type=int, help="the chunk ends at start + size - 1 when that is before --end")
    chunk.add_argument("--outputs", default="blend,obj", help=f"comma-separated: {', '.join(OUTPUTS)}")
    for sub in (chunk, commands.add_parser("assemble", help="assemble the baked chunks")):
        sub.add_argument("--directory", default="//animanifold_farm/")
        sub.add_argument("--object", default="", help="one manifold object (default: every one)")
    commands.choices["assemble"].add_argument("--outputs", default="blend,abc")
    commands.choices["assemble"].add_argument("--blend-name", default="assembled.blend")
    return parser


def main(argv: list[str] | None = None) -> None:
    """Runs a task from the arguments after `--` on Blender's command line (or `argv`); raises on
    failure, so `blender --python-exit-code 1` exits non-zero."""
    if argv is None:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = build_parser().parse_args(argv)
    if args.command == "bake-chunk":
        end = args.end
        if args.chunk_size is not None:
            if args.chunk_size < 1:
                raise FarmError(f"--chunk-size must be at least 1, got {args.chunk_size}")
            end = min(end, args.start + args.chunk_size - 1)
        bake_chunk(args.start, end, args.directory, args.object or None, args.outputs)
    else:
        assemble(args.directory, args.object or None, args.outputs, args.blend_name)


def _save_copy(path: str) -> None:
    """Saves a copy of the open file at `path`; the caches stay where the tasks share them."""
    with cache_follow.caches_stay_in_place():
        bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)

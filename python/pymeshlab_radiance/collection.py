"""The objects of a batch: a folder of meshes, or a manifest file listing them, each with the
photographs found beside it.

Folder: every mesh file under it (``.ply .rply .obj .off .stl .3ds .dae .wrl``, hidden folders and the
output folder skipped) is one object; its key is its path relative to the folder. Beside a mesh:
- a MeshLab project with the same name (``scan.ply`` + ``scan.mlp``), or the only ``.mlp`` of a folder
  holding a single mesh (``mesh.ply`` + ``project.mlp``, as ``tools/virtual_acquisition`` writes): its
  rasters are loaded (``MeshSet.load_project``) so the recipe can fit;
- a COLMAP model (``cameras.txt``/``cameras.bin`` in the folder, ``sparse/`` or ``sparse/0/``) or a
  Metashape camera export (``<name>.xml`` or ``cameras.xml`` with a ``<document>`` root): imported by
  the filter ``radiance_import_cameras_as_rasters(camerafile=, imagefolder=)`` when the installed
  plugins have it (the images from ``images/`` beside the mesh, else the mesh's folder); otherwise
  that object's row fails with the reason.

Manifest (any other file): one object per line, ``#`` comments, tab-separated fields
``MESH[<TAB>PROJECT-OR-CAMERAS[<TAB>IMAGEFOLDER]]``, paths relative to the manifest's folder.
"""

import hashlib
import os

MESH_EXTENSIONS = {".ply", ".rply", ".obj", ".off", ".stl", ".3ds", ".dae", ".wrl"}


class CollectionError(ValueError):
    pass


class Item:
    def __init__(self, key, mesh, project=None, cameras=None):
        self.key, self.mesh, self.project, self.cameras = key, mesh, project, cameras

    def files(self):
        """Every file whose content the job reads (for the input hash)."""
        files = [self.mesh] + ([self.project] if self.project else [])
        if self.cameras and os.path.isfile(self.cameras["camerafile"]):
            files.append(self.cameras["camerafile"])
        return files

    def sha256(self):
        digest = hashlib.sha256()
        for path in self.files():
            digest.update(os.path.basename(path).encode() + b"\0")
            with open(path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    digest.update(block)
        return digest.hexdigest()


def discover(input_path, exclude=None):
    """The objects of INPUT (a folder or a manifest file), sorted by key."""
    input_path = os.path.abspath(input_path)
    if os.path.isdir(input_path):
        items = _from_folder(input_path, exclude)
    elif os.path.isfile(input_path):
        items = _from_manifest(input_path)
    else:
        raise CollectionError(f"the input {input_path} does not exist: give a folder of meshes or a manifest file")
    if not items:
        raise CollectionError(f"no mesh found in {input_path} (extensions {' '.join(sorted(MESH_EXTENSIONS))})")
    return sorted(items, key=lambda item: item.key)


def _from_folder(root, exclude):
    exclude = os.path.abspath(exclude) if exclude else None
    items = []
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = sorted(d for d in subfolders if not d.startswith(".")
                               and os.path.join(folder, d) != exclude)
        meshes = sorted(f for f in files if os.path.splitext(f)[1].lower() in MESH_EXTENSIONS)
        for name in meshes:
            path = os.path.join(folder, name)
            key = os.path.relpath(path, root).replace(os.sep, "/")
            project = _project_beside(folder, name, files, meshes)
            items.append(Item(key, path, project, None if project else _cameras_beside(folder, name)))
    return items


def _project_beside(folder, name, files, meshes):
    same = os.path.splitext(name)[0] + ".mlp"
    if same in files:
        return os.path.join(folder, same)
    projects = [f for f in files if f.lower().endswith(".mlp")]
    if len(projects) == 1 and len(meshes) == 1:
        return os.path.join(folder, projects[0])
    return None


def _cameras_beside(folder, name):
    images = os.path.join(folder, "images")
    images = images if os.path.isdir(images) else folder
    for sub in ("", "sparse", os.path.join("sparse", "0")):
        for model in ("cameras.txt", "cameras.bin"):
            path = os.path.join(folder, sub, model)
            if os.path.isfile(path):
                return {"kind": "COLMAP", "camerafile": path, "imagefolder": images}
    for xml in (os.path.splitext(name)[0] + ".xml", "cameras.xml"):
        path = os.path.join(folder, xml)
        if os.path.isfile(path) and _is_metashape(path):
            return {"kind": "Metashape", "camerafile": path, "imagefolder": images}
    return None


def _is_metashape(path):
    with open(path, "rb") as f:
        head = f.read(2048)
    return b"<document" in head


def _from_manifest(path):
    base = os.path.dirname(path)
    items = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            fields = [field.strip() for field in line.split("\t")]
            mesh = os.path.normpath(os.path.join(base, fields[0]))
            key = os.path.relpath(mesh, base).replace(os.sep, "/")
            if key.startswith("../"):
                key = mesh.lstrip("/").replace(os.sep, "/")
            project, cameras = None, None
            if len(fields) > 1 and fields[1]:
                side = os.path.normpath(os.path.join(base, fields[1]))
                images = os.path.normpath(os.path.join(base, fields[2])) if len(fields) > 2 else os.path.dirname(mesh)
                if side.lower().endswith(".mlp"):
                    project = side
                elif side.lower().endswith(".xml"):
                    cameras = {"kind": "Metashape", "camerafile": side, "imagefolder": images}
                else:
                    cameras = {"kind": "COLMAP", "camerafile": side, "imagefolder": images}
            items.append(Item(key, mesh, project, cameras))
    return items

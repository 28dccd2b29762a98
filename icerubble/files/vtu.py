"""Field snapshots for ParaView: VTU (unstructured grid, XML, base64-free ASCII
for small scenes, raw-appended binary otherwise) plus a .pvd time collection.

Only numpy: no VTK dependency, so a run on a bare workstation can still write
files ParaView opens.
"""
import os
import xml.etree.ElementTree as ET

import numpy as np

_VTK_TRIANGLE = 5
_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.float32): "Float32",
          np.dtype(np.int32): "Int32", np.dtype(np.int64): "Int64",
          np.dtype(np.int8): "Int8", np.dtype(np.uint8): "UInt8"}


def _as_vtk_array(a):
    a = np.ascontiguousarray(a)
    if a.dtype not in _TYPES:
        a = a.astype(np.float64)
    return a


def write_vtu(path, nodes, triangles, point_data=None, cell_data=None):
    """Write a triangle mesh with point and cell fields to `path` (.vtu).

    nodes (N,2) or (N,3); triangles (M,3); fields are (N,) / (N,k) and (M,) / (M,k)
    arrays. 2-component vectors are padded to 3 so ParaView treats them as vectors.
    Data go to an appended raw binary block (little endian, UInt64 headers).
    """
    nodes = np.asarray(nodes, dtype=np.float64)
    if nodes.shape[1] == 2:
        nodes = np.column_stack([nodes, np.zeros(len(nodes))])
    tri = np.asarray(triangles, dtype=np.int64)
    n, m = len(nodes), len(tri)
    blocks = []
    offset = [0]

    def add(parent, name, arr):
        arr = _as_vtk_array(arr)
        if arr.ndim == 2 and arr.shape[1] == 2:
            arr = np.column_stack([arr, np.zeros(len(arr), arr.dtype)])
        ncomp = 1 if arr.ndim == 1 else arr.shape[1]
        el = ET.SubElement(parent, "DataArray", type=_TYPES[arr.dtype], Name=name,
                           NumberOfComponents=str(ncomp), format="appended", offset=str(offset[0]))
        raw = arr.astype(arr.dtype.newbyteorder("<"), copy=False).tobytes()
        blocks.append(np.uint64(len(raw)).tobytes() + raw)
        offset[0] += 8 + len(raw)
        return el

    root = ET.Element("VTKFile", type="UnstructuredGrid", version="1.0",
                      byte_order="LittleEndian", header_type="UInt64")
    grid = ET.SubElement(root, "UnstructuredGrid")
    piece = ET.SubElement(grid, "Piece", NumberOfPoints=str(n), NumberOfCells=str(m))
    pd = ET.SubElement(piece, "PointData")
    for k, v in (point_data or {}).items():
        add(pd, k, v)
    cd = ET.SubElement(piece, "CellData")
    for k, v in (cell_data or {}).items():
        add(cd, k, v)
    add(ET.SubElement(piece, "Points"), "Points", nodes)
    cells = ET.SubElement(piece, "Cells")
    add(cells, "connectivity", tri.reshape(-1))
    add(cells, "offsets", np.arange(3, 3 * m + 1, 3, dtype=np.int64))
    add(cells, "types", np.full(m, _VTK_TRIANGLE, dtype=np.uint8))
    head = ET.tostring(root, encoding="unicode")
    # the appended block must sit inside VTKFile, after the grid
    head = head.replace("</VTKFile>", "")
    tmp = os.fspath(path) + ".part"
    with open(tmp, "wb") as f:
        f.write(b'<?xml version="1.0"?>\n')
        f.write(head.encode())
        f.write(b'\n<AppendedData encoding="raw">\n_')
        for b in blocks:
            f.write(b)
        f.write(b"\n</AppendedData>\n</VTKFile>\n")
    os.replace(tmp, path)


def write_pvd(path, entries):
    """A ParaView time collection: entries is a list of (time, vtu file name)."""
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for t, name in entries:
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part="0", file=name)
    tmp = os.fspath(path) + ".part"
    ET.ElementTree(root).write(tmp, xml_declaration=True, encoding="utf-8")
    os.replace(tmp, path)


def read_vtu(path):
    """Read back what write_vtu wrote (for tests and quick checks)."""
    data = open(path, "rb").read()
    start = data.index(b'<AppendedData encoding="raw">')
    xml_head = data[:start].decode() + "</VTKFile>"
    raw = data[data.index(b"_", start) + 1:]
    root = ET.fromstring(xml_head.split("?>", 1)[1])
    piece = root.find("UnstructuredGrid/Piece")
    inv = {v: k for k, v in _TYPES.items()}
    out = {}
    for el in piece.iter("DataArray"):
        off = int(el.get("offset"))
        nbytes = int(np.frombuffer(raw[off:off + 8], "<u8")[0])
        arr = np.frombuffer(raw[off + 8:off + 8 + nbytes], inv[el.get("type")].newbyteorder("<"))
        nc = int(el.get("NumberOfComponents"))
        out[el.get("Name")] = arr.reshape(-1, nc) if nc > 1 else arr
    return out

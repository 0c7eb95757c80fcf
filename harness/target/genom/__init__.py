"""GenoM3 component descriptions (`.gen`): the reader (preprocess.py, dotgen.lark, reader.py) and
what `untimely init --from-genom` derives from them (derive.py)."""

"""The type stubs declare every public name, with the arguments the
functions take."""

import ast
import inspect
import pathlib

import imutherm

STUB = pathlib.Path(imutherm.__file__).with_name("__init__.pyi")


def stub_definitions():
    tree = ast.parse(STUB.read_text())
    defs = {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            defs[node.name] = node
        elif isinstance(node, ast.ImportFrom):
            for alias in node.names:
                defs[alias.asname or alias.name] = node
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                defs[getattr(t, "id", None)] = node
    return defs


def test_every_public_name_is_declared():
    defs = stub_definitions()
    assert sorted(set(imutherm.__all__) - set(defs)) == []


def test_function_arguments_match():
    defs = stub_definitions()
    for name in ("read", "simulate", "tcal_fit", "analyze", "noise_terms"):
        stub_args = [a.arg for a in defs[name].args.args]
        assert stub_args == list(inspect.signature(getattr(imutherm, name)).parameters), name

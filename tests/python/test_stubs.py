# The type stubs name exactly what the module defines, and every public callable has a docstring.
import ast
import inspect
import os

import minksum as mk

STUBS = os.path.join(os.path.dirname(mk.__file__), "minksum.pyi")


def stub_names():
    tree = ast.parse(open(STUBS).read())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    return {n for n in names if not n.startswith("_") or n == "__version__"} - {"ArrayLike", "Array", "IntArray", "Pose",
                                                                                "PathLike"}


def test_stubs_match_the_module():
    public = {name for name in dir(mk) if not name.startswith("_")} | {"__version__"}
    assert stub_names() == public


def test_every_public_callable_is_documented():
    for name in dir(mk):
        if name.startswith("_"):
            continue
        value = getattr(mk, name)
        assert value.__doc__ and len(value.__doc__.strip()) > 20, name
        if inspect.isclass(value) and not hasattr(value, "__members__"):  # enums: pybind11's own members
            for member, item in vars(value).items():
                if not member.startswith("_") and callable(getattr(item, "__get__", None)) and hasattr(item, "__doc__"):
                    assert item.__doc__, f"{name}.{member}"

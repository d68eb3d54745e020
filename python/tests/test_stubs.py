"""The type stub lists every keyword of the library with its default: the parameter lines of
ridgeline/__init__.pyi are generated from ridgeline.default_params(), and this test fails when
they are out of date (RIDGELINE_BLESS=1 rewrites them)."""

import ast
import inspect
import os
import re
from pathlib import Path

import ridgeline

STUB = Path(__file__).resolve().parents[1] / "ridgeline" / "__init__.pyi"
BEGIN = "    # parameters (generated from default_params(): RIDGELINE_BLESS=1 pytest tests/test_stubs.py)\n"
END = "    # end of parameters\n"


def rendered() -> str:
    kinds = {bool: "bool", int: "int", float: "float", str: "str", list: "list[str]"}
    lines = []
    for name, value in ridgeline.default_params().items():
        if isinstance(value, dict):
            lines.append(f"    {name}: Mapping[str, Any] = ...,  # default {value!r}\n")
        elif value is None:
            lines.append(f"    {name}: Any = None,\n")
        else:
            lines.append(f"    {name}: {kinds[type(value)]} = {value!r},\n")
    return "".join(lines)


def test_the_stub_lists_every_parameter_with_its_default():
    text = STUB.read_text()
    pattern = re.compile(re.escape(BEGIN) + r"(.*?)" + re.escape(END), re.S)
    blocks = pattern.findall(text)
    assert len(blocks) == 3, "trace, trace_pages and trace_points each carry the block"
    if os.environ.get("RIDGELINE_BLESS"):
        STUB.write_text(pattern.sub(lambda _: BEGIN + rendered() + END, text))
        return
    for block in blocks:
        assert block == rendered(), "the stub is out of date: RIDGELINE_BLESS=1 pytest tests/test_stubs.py"


def test_the_stub_and_the_runtime_signature_agree():
    tree = ast.parse(STUB.read_text())
    functions = {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}
    for name in ["trace", "trace_pages", "trace_points"]:
        stub_names = [a.arg for a in functions[name].args.kwonlyargs]
        runtime = inspect.signature(getattr(ridgeline, name)).parameters
        keywords = [p for p in runtime.values() if p.kind is inspect.Parameter.KEYWORD_ONLY]
        assert stub_names == [p.name for p in keywords]
        assert stub_names[:2] == ["source_path", "threads"]
        assert stub_names[2:] == list(ridgeline.default_params())


def test_every_public_name_has_a_docstring_and_a_stub():
    tree = ast.parse(STUB.read_text())
    stubbed = {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
    # The exceptions are re-exported from ridgeline/_errors.py, which is typed itself.
    stubbed |= {alias.asname for node in tree.body if isinstance(node, ast.ImportFrom) for alias in node.names}
    for name in ridgeline.__all__:
        if name == "__version__":
            continue
        assert name in stubbed, name
        assert getattr(ridgeline, name).__doc__, name
    trace_class = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Trace")
    stub_members = {n.name for n in trace_class.body if isinstance(n, ast.FunctionDef)}
    runtime_members = {m for m in dir(ridgeline.Trace) if not m.startswith("_")}
    assert stub_members - {"__repr__"} == runtime_members
    for member in runtime_members:
        assert getattr(ridgeline.Trace, member).__doc__, member

"""The type stub (``kinetree/__init__.pyi``) against the extension itself, as mypy's stubtest
would: every public method and property of the classes exists on both sides, and each method's
parameters (names, kinds, defaults) are the runtime signature's."""

import ast
import inspect
import pathlib

import pytest

import kinetree

STUB = pathlib.Path(kinetree.__file__).with_name("__init__.pyi")


def stub_classes():
    """class name -> {member name: FunctionDef (the first overload) or "property"}."""
    tree = ast.parse(STUB.read_text())
    classes = {}
    for node in tree.body:
        if not isinstance(node, ast.ClassDef):
            continue
        members = {}
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                decorators = {getattr(d, "id", getattr(d, "attr", None)) for d in item.decorator_list}
                if "property" in decorators:
                    members[item.name] = "property"
                else:
                    members.setdefault(item.name, item)
            elif isinstance(item, ast.AnnAssign):
                members[item.target.id] = "attribute"
        classes[node.name] = members
    return classes


CLASSES = stub_classes()


def stub_parameters(fn, is_static):
    """(name, kind, default) of a stub function's parameters, without ``self``."""
    args = fn.args
    positional = args.posonlyargs + args.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(args.defaults)) + [
        ast.literal_eval(d) for d in args.defaults
    ]
    params = []
    for i, (a, d) in enumerate(zip(positional, defaults)):
        kind = (inspect.Parameter.POSITIONAL_ONLY if i < len(args.posonlyargs)
                else inspect.Parameter.POSITIONAL_OR_KEYWORD)
        params.append((a.arg, kind, d))
    for a, d in zip(args.kwonlyargs, args.kw_defaults):
        default = inspect.Parameter.empty if d is None else ast.literal_eval(d)
        params.append((a.arg, inspect.Parameter.KEYWORD_ONLY, default))
    if not is_static and params and params[0][0] == "self":
        params = params[1:]
    return params


def runtime_parameters(obj):
    params = []
    for p in inspect.signature(obj).parameters.values():
        if p.name == "self":
            continue
        # PyO3 marks `self` positional-only; the stub's parameters are ordinary ones.
        kind = (inspect.Parameter.POSITIONAL_OR_KEYWORD
                if p.kind == inspect.Parameter.POSITIONAL_ONLY else p.kind)
        params.append((p.name, kind, p.default))
    return params


@pytest.mark.parametrize("name", sorted(CLASSES))
def test_the_stub_lists_what_the_class_has(name):
    cls = getattr(kinetree, name)
    stub = CLASSES[name]
    runtime = {n for n in vars(cls) if not n.startswith("_")}
    if issubclass(cls, BaseException):
        return
    stubbed = {n for n in stub if not n.startswith("_")}
    assert runtime == stubbed, (sorted(runtime - stubbed), sorted(stubbed - runtime))


METHODS = [(c, m) for c, members in CLASSES.items() for m, f in members.items()
           if isinstance(f, ast.FunctionDef) and (not m.startswith("_") or m == "__init__")]


@pytest.mark.parametrize("cls, method", METHODS)
def test_the_stub_signature_is_the_runtime_signature(cls, method):
    fn = CLASSES[cls][method]
    is_static = any(getattr(d, "id", None) == "staticmethod" for d in fn.decorator_list)
    obj = getattr(kinetree, cls) if method == "__init__" else getattr(getattr(kinetree, cls), method)
    if method != "__init__" and not is_static:
        assert not isinstance(inspect.getattr_static(getattr(kinetree, cls), method), staticmethod)
    assert stub_parameters(fn, is_static) == runtime_parameters(obj)


def test_properties_are_properties():
    for cls, members in CLASSES.items():
        for name, what in members.items():
            if what == "property":
                attr = inspect.getattr_static(getattr(kinetree, cls), name)
                assert not callable(attr), (cls, name)

import importlib.util
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def load_tool(name: str):
    """A script of tools/ as a module: tools/ is not a package, so it cannot be imported by name."""
    spec = importlib.util.spec_from_file_location(f"tools_{name}", ROOT / "tools" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module   # dataclasses look their module up there while the class is made
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def docs_tables():
    return load_tool("docs_tables")


@pytest.fixture(scope="session")
def docs_commands():
    return load_tool("docs_commands")

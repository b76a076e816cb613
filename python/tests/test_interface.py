"""The module's surface as a notebook meets it: a namespace that holds the module's names only."""

import types

import slidespec as ss


def test_the_namespace_holds_the_modules_names_only():
    public = {name for name in dir(ss) if not name.startswith("_")}
    assert public == set(ss.__all__), public ^ set(ss.__all__)
    assert not [name for name in public if isinstance(getattr(ss, name), types.ModuleType)]
    for name in ("np", "os", "re", "json", "math", "stat", "errno", "warnings", "Mapping"):
        assert not hasattr(ss, name), name

"""One progress adapter (issue 17): both callback forms, errors inside a callback are not swallowed."""

import ast
import os

import pytest

from radiometer.progress import reporter

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_three_and_two_argument_callbacks():
    calls = []
    reporter(lambda done, total, seconds_left: calls.append((done, total, seconds_left)))(3, 10, 4.5)
    reporter(lambda done, total: calls.append((done, total)))(4, 10, 2.0)
    reporter(lambda *args: calls.append(args))(5, 10)
    reporter(lambda done, total, *rest: calls.append((done, total) + rest))(6, 10, None)

    class Bar:
        def update(self, done, total, seconds_left=None):
            calls.append(("bar", done, total, seconds_left))

    reporter(Bar().update)(7, 10, 1.0)
    assert calls == [(3, 10, 4.5), (4, 10), (5, 10, None), (6, 10, None), ("bar", 7, 10, 1.0)]
    assert reporter(None) is None
    once = reporter(print)
    assert reporter(once) is once


def test_a_type_error_inside_the_callback_reaches_the_caller_once():
    calls = []

    def broken(done, total, seconds_left):
        calls.append(done)
        raise TypeError("bug in the user's callback")

    with pytest.raises(TypeError, match="bug in the user's callback"):
        reporter(broken)(1, 2, None)
    assert calls == [1]  # not retried with two arguments


def test_no_module_catches_type_error_around_a_progress_call():
    offenders = []
    for root, dirs, files in os.walk(REPO):
        dirs[:] = [d for d in dirs if not d.startswith(".") and d not in {"tests", "bench", "docs", "tools", "out"}]
        for name in files:
            if not name.endswith(".py"):
                continue
            path = os.path.join(root, name)
            for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
                if not isinstance(node, ast.Try):
                    continue
                catches = any(h.type is not None and "TypeError" in ast.unparse(h.type) for h in node.handlers)
                calls = [c for stmt in node.body for c in ast.walk(stmt) if isinstance(c, ast.Call)
                         and "progress" in ast.unparse(c.func).lower()]
                if catches and calls:
                    offenders.append(f"{os.path.relpath(path, REPO)}:{node.lineno}")
    assert not offenders, f"use radiometer.progress.reporter instead: {offenders}"

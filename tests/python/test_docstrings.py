"""Every public call of the taskmap package has a docstring the generated reference can stand on
(issue 53; tools/docs/reference.py renders them):

- a class: an example;
- a function or method: ``Args:`` naming every parameter of its signature (when it takes any),
  ``Returns:``, ``Raises:`` (or the sentence "Raises nothing.") and ``Example:`` sections;
- a parameter or property whose name says it is a length, a pose, an angle or a gradient states
  its units (metres, radians, ...) and, for poses and gradients, its frame (see UNITS below);
- a property: at least a line."""
import inspect
import re
import unittest

import taskmap

# Parameter and property names that carry a physical quantity, and what their description must
# name: a unit word, and for poses, Jacobians and gradients a frame too.
LENGTH = re.compile(r"(^|_)(pose|poses|position|offset|offsets|distance|distances|radius|r|"
                    r"tolerance|standoff|margin|alpha|threshold|zone|patch|glyph_size|sigma|"
                    r"translation|target|world|points|depths)($|_)")
ANGLE = re.compile(r"(^|_)(angle|rotation|rho|q|q0|lower|upper|rotation_scale)($|_)")
FRAMED = re.compile(r"(^|_)(pose|poses|target|world|gradient|jacobian|points|normals)($|_)")
GRADIENT = re.compile(r"(^|_)(gradient|jacobian)($|_)")
UNIT_WORDS = re.compile(r"\b(metres?|meters?|m|mm|cm|radians?|rad|degrees?|deg|1/m\^2|"
                        r"1/rad\^2)\b")
ANGLE_WORDS = re.compile(r"\b(radians?|rad|degrees?|deg|metres per radian|1/rad\^2)\b")
FRAME_WORDS = re.compile(r"\b(frame|world|object frame|in the object)\b")
# Parameters that match a pattern above but are not quantities (a file, a callable, a count).
NOT_QUANTITIES = {
    "contact_offsets",  # row offsets into the contact arrays, not lengths
}
SECTION = re.compile(r"^(Args|Other Parameters|Returns|Raises|Example|Examples):\s*$", re.M)


def public_names():
    return [n for n in dir(taskmap) if not n.startswith("_")]


def callables():
    """(qualified name, object) of every public function and method."""
    out = []
    for name in public_names():
        obj = getattr(taskmap, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            for attr in vars(obj):
                if not attr.startswith("_") and callable(getattr(obj, attr)):
                    out.append((f"{name}.{attr}", getattr(obj, attr)))
        elif callable(obj):
            out.append((name, obj))
    return out


def properties():
    out = []
    for name in public_names():
        cls = getattr(taskmap, name)
        if inspect.isclass(cls) and not issubclass(cls, BaseException):
            for attr, value in vars(cls).items():
                if not attr.startswith("_") and isinstance(value, property):
                    out.append((f"{name}.{attr}", attr, value.__doc__ or ""))
    return out


def sections(doc):
    """{section title: its text} of a Google-style docstring."""
    parts = SECTION.split(doc)
    return {parts[i]: parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def documented_params(text):
    """{name: description} of an Args or Other Parameters section."""
    params, cur = {}, None
    for line in text.split("\n"):
        m = re.match(r"^    (\*{0,2}\w+)\s*(\([^)]*\))?:\s*(.*)$", line)
        if m:
            cur = m.group(1).lstrip("*")
            params[cur] = m.group(3)
        elif cur and line.startswith("        "):
            params[cur] += " " + line.strip()
    return params


def signature_params(obj):
    """Parameter names of the signature on a docstring's first line (pybind11) or inspect's."""
    first = (obj.__doc__ or "").lstrip().split("\n", 1)[0]
    m = re.match(r"^\w+\((.*)\)\s*(->.*)?$", first)
    if m:
        names = re.findall(r"(?:^|,\s*)\*{0,2}(\w+)(?=\s*[:=,]|\s*$)", m.group(1))
    else:
        try:
            names = list(inspect.signature(obj).parameters)
        except (TypeError, ValueError):
            names = []
    return [n for n in names if n not in ("self", "args")]


def quantity_errors(name, description):
    """What a parameter's (or property's) description lacks, by its name."""
    errors = []
    if name in NOT_QUANTITIES:
        return errors
    if LENGTH.search(name) and not UNIT_WORDS.search(description):
        errors.append("no unit (metres, radians, ...)")
    if ANGLE.search(name) and not (ANGLE_WORDS.search(description)
                                   or UNIT_WORDS.search(description)):
        errors.append("no angle unit (radians, degrees)")
    if GRADIENT.search(name) and not re.search(r"\b(per metre|per radian|metres?|radians?)\b",
                                               description):
        errors.append("no units of its rows (per metre, per radian)")
    if FRAMED.search(name) and not FRAME_WORDS.search(description):
        errors.append("no frame")
    return errors


class DocstringTest(unittest.TestCase):
    def test_every_class_has_an_example(self):
        names = public_names()
        self.assertGreater(len(names), 25)
        for name in names:
            obj = getattr(taskmap, name)
            if not (callable(obj) or inspect.isclass(obj)):
                continue
            with self.subTest(name=name):
                doc = obj.__doc__ or ""
                self.assertTrue(doc.strip(), f"taskmap.{name} has no docstring")
                self.assertIn("Example", doc, f"taskmap.{name}'s docstring has no example")

    def test_every_call_has_args_returns_raises_and_an_example(self):
        calls = callables()
        self.assertGreater(len(calls), 40)
        for name, obj in calls:
            with self.subTest(name=name):
                doc = obj.__doc__ or ""
                found = sections(doc)
                params = signature_params(obj)
                wanted = (["Args"] if params else []) + ["Returns", "Raises", "Example"]
                for title in wanted:
                    if title == "Raises" and "Raises nothing." in doc:
                        continue
                    self.assertTrue(title in found or (title == "Example" and "Examples" in found),
                                    f"taskmap.{name}'s docstring has no {title}: section")
                documented = documented_params(found.get("Args", ""))
                documented.update(documented_params(found.get("Other Parameters", "")))
                for p in params:
                    if p in ("kwargs", "options", "knobs"):
                        continue
                    self.assertIn(p, documented, f"taskmap.{name}: parameter {p} not in Args")

    def test_quantities_state_units_and_frames(self):
        checked = 0
        for name, obj in callables():
            found = sections(obj.__doc__ or "")
            documented = documented_params(found.get("Args", ""))
            documented.update(documented_params(found.get("Other Parameters", "")))
            for p, description in documented.items():
                errors = quantity_errors(p, description)
                checked += 1
                with self.subTest(name=f"{name}({p})"):
                    self.assertFalse(errors, f"taskmap.{name}, parameter {p}: "
                                     f"{'; '.join(errors)}: {description!r}")
        for qualified, attr, doc in properties():
            errors = quantity_errors(attr, doc)
            checked += 1
            with self.subTest(name=qualified):
                self.assertFalse(errors, f"taskmap.{qualified}: {'; '.join(errors)}: {doc!r}")
        self.assertGreater(checked, 150)

    def test_every_method_and_property_has_a_docstring(self):
        for name in public_names():
            cls = getattr(taskmap, name)
            if not inspect.isclass(cls) or issubclass(cls, BaseException):
                continue
            for attr in vars(cls):
                if attr.startswith("_"):
                    continue
                with self.subTest(name=f"{name}.{attr}"):
                    doc = getattr(cls, attr).__doc__ or ""
                    self.assertTrue(doc.strip(), f"taskmap.{name}.{attr} has no docstring")


if __name__ == "__main__":
    unittest.main()

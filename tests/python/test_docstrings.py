"""Every public call of the taskmap package has a docstring: functions and classes with an
example, methods and properties at least a line (issue 53; the generated reference renders
them, tools/docs/reference.py)."""
import inspect
import unittest

import taskmap


def public_names():
    return [n for n in dir(taskmap) if not n.startswith("_")]


class DocstringTest(unittest.TestCase):
    def test_every_function_and_class_has_an_example(self):
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

    def test_functions_state_their_arguments(self):
        for name in ("build", "load", "validate", "reach", "mesh_info", "hand_info", "view"):
            with self.subTest(name=name):
                doc = getattr(taskmap, name).__doc__
                self.assertIn("Args:", doc)
                self.assertIn("Returns:", doc)
                self.assertIn("Raises:", doc)


if __name__ == "__main__":
    unittest.main()

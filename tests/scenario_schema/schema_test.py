"""docs/scenario.schema.json against the scenario reader: every shipped scenario
validates; broken scenarios the reader refuses, the schema refuses too; and the
keys, names and ranges the schema lists are those the reader and the tables
it is documented by (docs/algorithms/README.md, traces/README.md,
docs/metric-table.md, each checked against `hapticbench list` by the C++ tests)
accept, so that the two cannot drift apart silently. Run by CTest with
Debian's python3 (package python3-jsonschema)."""
import glob
import json
import os
import re
import sys
import unittest

try:
    import jsonschema
except ImportError:
    sys.exit("schema_test: the Python module jsonschema is missing; install the Debian package "
             "python3-jsonschema (scripts/setup installs it) and run /usr/bin/python3")

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCHEMA_PATH = os.path.join(ROOT, "docs", "scenario.schema.json")
INT64_MAX = 2**63 - 1

# JSON files among the scenarios' folders that are not scenarios.
NOT_SCENARIOS = {
    "examples/ci/tolerances.json": "compare's tolerances (docs/ci-gating.md)",
}


def read_text(*parts):
    with open(os.path.join(ROOT, *parts), encoding="utf-8") as f:
        return f.read()


def without_comments(text):
    """The text with // and /* */ comments outside strings blanked, as the
    reader's parser skips them (harness/scenario/json_fields.cpp)."""
    out, i, in_string = [], 0, False
    while i < len(text):
        c = text[i]
        if in_string:
            out.append(c)
            if c == "\\":
                out.append(text[i + 1:i + 2])
                i += 1
            elif c == '"':
                in_string = False
        elif text.startswith("//", i) or text.startswith("/*", i):
            end = text.find("\n", i) if text[i + 1] == "/" else text.find("*/", i + 2) + 2
            end = len(text) if end < i + 2 else end
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        else:
            in_string = c == '"'
            out.append(c)
        i += 1
    return "".join(out)


def load_json(*parts):
    return json.loads(without_comments(read_text(*parts)))


SCHEMA = load_json("docs", "scenario.schema.json")
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)


def resolve(pointer):
    """The schema node at a JSON pointer of the schema file ("#/$defs/tool")."""
    node = SCHEMA
    for token in pointer.lstrip("#/").split("/") if pointer.lstrip("#/") else []:
        node = node[token.replace("~1", "/").replace("~0", "~")]
    return node


def table_rows(path, columns):
    """Rows of the Markdown tables in a file whose first cell is `code`."""
    rows = []
    for line in read_text(path).splitlines():
        if line.startswith("| `"):
            cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
            if len(cells) == columns:
                rows.append([cell.strip("`") if i < 2 else cell for i, cell in enumerate(cells)])
    return rows


def number(text):
    value = float(text)
    return int(value) if value == int(value) else value


def constraints_of_accepted(accepted):
    """The schema constraints that `hapticbench list`'s "accepted" text means."""
    match = re.fullmatch(r"one of (.*)", accepted)
    if match:
        return {"type": "string", "enum": re.findall(r'"([^"]*)"', match.group(1))}
    match = re.fullmatch(r"(whole )?number in \[([^,]+), ([^\]]+)\]", accepted)
    if match:
        return {"type": "integer" if match.group(1) else "number",
                "minimum": number(match.group(2)), "maximum": number(match.group(3))}
    match = re.fullmatch(r"(whole )?number >= (\S+)", accepted)
    if match:
        return {"type": "integer" if match.group(1) else "number",
                "minimum": number(match.group(2))}
    if accepted == "true or false":
        return {"type": "boolean"}
    match = re.fullmatch(r"list of (\d+) numbers", accepted)
    if match:
        return {"type": "array", "minItems": int(match.group(1)), "maxItems": int(match.group(1))}
    raise AssertionError(f"an accepted text the test does not know: {accepted!r}")


CONSTRAINT_KEYS = ("type", "enum", "minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum",
                   "minItems", "maxItems")


def constraints_of(node):
    return {key: node[key] for key in CONSTRAINT_KEYS if key in node}


# Where the schema says more than the table's "accepted" text, as the code
# does: (owner, parameter) -> the schema's constraints.
CONSTRAINT_OVERRIDES = {
    # read_proxy_mass refuses 0 after reading a number >= 0.
    ("*", "proxy_mass_kg"): {"type": "number", "exclusiveMinimum": 0},
    # At most haptic_band (itself at most 1); the table shows the default band.
    ("*", "haptic_band_min"): {"type": "number", "minimum": 1e-06, "maximum": 1},
    # constrained_dynamics refuses 0 ("expected a fraction in (0, 1]").
    ("constrained_dynamics", "stabilisation"): {"type": "number", "exclusiveMinimum": 0,
                                                "maximum": 1},
    # Two or more waypoints of 3 numbers; the table shows the default's six.
    ("path", "points"): {"type": "array", "minItems": 6},
    # In [0, duration_s]; the table shows a 1 s trace.
    ("jump", "at_s"): {"type": "number", "minimum": 0},
    # generate_human_like refuses 0 and 10 ("expected a cutoff in (0, 10) Hz").
    ("human_like", "cutoff_hz"): {"type": "number", "exclusiveMinimum": 0, "exclusiveMaximum": 10},
}


def expected_constraints(owner, parameter, accepted):
    for key in ((owner, parameter), ("*", parameter)):
        if key in CONSTRAINT_OVERRIDES:
            return CONSTRAINT_OVERRIDES[key]
    return constraints_of_accepted(accepted)


def error_pointers(errors):
    """JSON pointers of every error, including those nested in anyOf/oneOf."""
    pointers = []
    for error in errors:
        pointers.append("/" + "/".join(str(part) for part in error.absolute_path))
        pointers.extend(error_pointers(error.context or []))
    return pointers


class SchemaFileTest(unittest.TestCase):
    def test_is_a_valid_draft_2020_12_schema(self):
        self.assertEqual(SCHEMA["$schema"], "https://json-schema.org/draft/2020-12/schema")
        jsonschema.Draft202012Validator.check_schema(SCHEMA)

    def test_every_reference_resolves(self):
        text = read_text("docs", "scenario.schema.json")
        for pointer in set(re.findall(r'"\$ref": "(#[^"]*)"', text)):
            with self.subTest(pointer=pointer):
                resolve(pointer)


class ShippedScenariosTest(unittest.TestCase):
    def scenario_files(self):
        files = [path for path in glob.glob(os.path.join(ROOT, "scenarios", "**", "*.json"),
                                            recursive=True)
                 if os.path.dirname(path) != os.path.join(ROOT, "scenarios", "sweeps")]
        files += glob.glob(os.path.join(ROOT, "examples", "**", "*.json"), recursive=True)
        files += glob.glob(os.path.join(ROOT, "tests", "recipe", "*.json"))
        relative = sorted(os.path.relpath(path, ROOT) for path in files)
        return [path for path in relative if path not in NOT_SCENARIOS]

    def test_every_shipped_scenario_validates(self):
        files = self.scenario_files()
        self.assertIn("scenarios/smoke/sphere_press_box.json", files)
        self.assertIn("examples/out_of_tree_renderer/sphere_press_box.json", files)
        self.assertIn("tests/recipe/my_algo_press.json", files)
        for path in files:
            with self.subTest(scenario=path):
                errors = sorted(VALIDATOR.iter_errors(load_json(path)), key=str)
                self.assertEqual(
                    [], ["/" + "/".join(map(str, e.absolute_path)) + ": " + e.message
                         for e in errors])

    def test_the_files_left_out_exist(self):
        for path in NOT_SCENARIOS:
            self.assertTrue(os.path.isfile(os.path.join(ROOT, path)), path)


def edit(*changes):
    """A scenario edit: (pointer, value) sets, (pointer, DELETE) removes."""
    def apply(scenario):
        for pointer, value in changes:
            tokens = pointer.strip("/").split("/")
            node = scenario
            for token in tokens[:-1]:
                node = node[int(token)] if isinstance(node, list) else node[token]
            last = int(tokens[-1]) if isinstance(node, list) else tokens[-1]
            if value is DELETE:
                del node[last]
            else:
                node[last] = value
        return scenario
    return apply


DELETE = object()
MASS_NOT_DENSITY = (("/tool/density", DELETE), ("/tool/mass_kg", 0.03))

# Scenarios the reader refuses (`hapticbench validate` exits 2), each an edit
# of scenarios/smoke/sphere_press_box.json, and where (at or under) the schema
# must say so.
BROKEN = {
    "an unknown top-level key": (edit(("/colour", "red")), "/"),
    "a \"$schema\" key (the reader knows no such key)": (edit(("/$schema", "x.json")), "/"),
    "a misspelled coupling key": (edit(("/coupling/kt", 2000)), "/coupling"),
    "a negative k_t": (edit(("/coupling/k_t", -1)), "/coupling/k_t"),
    "a zero k_t": (edit(("/coupling/k_t", 0)), "/coupling/k_t"),
    "a negative b_t": (edit(("/coupling/b_t", -1)), "/coupling/b_t"),
    "a sphere without radius": (edit(("/tool/shape/radius", DELETE)), "/tool/shape"),
    "an unknown shape type": (edit(("/tool/shape/type", "cylinder")), "/tool/shape/type"),
    "a box with a radius": (edit(("/scene/0/shape/radius", 0.1)), "/scene/0/shape"),
    "7 subdivisions": (edit(("/tool/shape/subdivisions", 7)), "/tool/shape/subdivisions"),
    "a capsule of negative length": (
        edit(("/tool/shape", {"type": "capsule", "radius": 0.01, "length": -1})),
        "/tool/shape/length"),
    "an unknown budget name": (edit(("/budgets/tick_p99", 1000)), "/budgets"),
    "a budget that is not a number": (edit(("/budgets/nonfinite", "0")), "/budgets/nonfinite"),
    "an unknown pose key": (edit(("/scene/0/pose/r", [0, 0, 0])), "/scene/0/pose"),
    "a quaternion of 3 numbers": (edit(("/scene/0/pose/q", [1, 0, 0])), "/scene/0/pose/q"),
    "an empty scene": (edit(("/scene", [])), "/scene"),
    "a negative friction": (edit(("/scene/0/friction", -0.1)), "/scene/0/friction"),
    "density and mass_kg": (edit(("/tool/mass_kg", 0.1)), "/tool"),
    "inertia without mass_kg": (edit(("/tool/inertia", [1e-6, 1e-6, 1e-6])), "/tool"),
    "a non-positive principal moment": (
        edit(*MASS_NOT_DENSITY, ("/tool/inertia", [-1e-6, 1e-6, 1e-6])), "/tool/inertia"),
    "scale on a shape": (edit(("/tool/scale", 2)), "/tool"),
    "a mesh and a shape": (edit(("/tool/mesh", "models/bunny00.off")), "/tool"),
    "no geometry": (edit(("/tool/shape", DELETE)), "/tool"),
    "a trace file and a generator": (edit(("/trace/file", "traces/press_sphere.csv")), "/trace"),
    "an unknown generator": (edit(("/trace/generator", "poke")), "/trace/generator"),
    "a generator without duration_s": (edit(("/trace/duration_s", DELETE)), "/trace"),
    "a duration of 0 s": (edit(("/trace/duration_s", 0)), "/trace/duration_s"),
    "a duration over an hour": (edit(("/trace/duration_s", 3601)), "/trace/duration_s"),
    "a negative seed": (edit(("/trace/seed", -1)), "/trace/seed"),
    "a seed that is not whole": (edit(("/trace/seed", 1.5)), "/trace/seed"),
    "an unknown generator parameter": (edit(("/trace/params/deep", 1)), "/trace/params"),
    "a generator parameter out of range": (edit(("/trace/params/depth", 2)),
                                           "/trace/params/depth"),
    "a generator parameter of the wrong kind": (edit(("/trace/params/start", 0.03)),
                                                "/trace/params/start"),
    "a trace file with a seed": (
        edit(("/trace", {"file": "traces/press_sphere.csv", "seed": 1})), "/trace"),
    "an unknown trace format": (
        edit(("/trace", {"file": "traces/press_sphere.csv", "format": "xml"})), "/trace/format"),
    "unknown trace units": (
        edit(("/trace", {"file": "traces/press_sphere.csv", "units": "inch"})), "/trace/units"),
    "no algorithms": (edit(("/algorithms", [])), "/algorithms"),
    "an algorithm without name": (edit(("/algorithms/0/name", DELETE)), "/algorithms/0"),
    "a label with a slash": (edit(("/algorithms/0/label", "a/b")), "/algorithms/0/label"),
    "an unknown algorithm entry key": (edit(("/algorithms/0/colour", 1)), "/algorithms/0"),
    "an unknown algorithm parameter": (edit(("/algorithms/1/params/stiffness", 1)),
                                       "/algorithms/1/params"),
    "an algorithm parameter out of range": (
        edit(("/algorithms/1/params/contact_stiffness", -1)),
        "/algorithms/1/params/contact_stiffness"),
    "an unknown integrator": (edit(("/algorithms/1/params/integrator", "rk4")),
                              "/algorithms/1/params/integrator"),
    "a quasi-static proxy with an integrator": (
        edit(("/algorithms/3/params/integrator", "implicit_euler")), "/algorithms/3/params"),
    "a zero proxy mass": (edit(("/algorithms/0/params", {"proxy_mass_kg": 0})),
                          "/algorithms/0/params/proxy_mass_kg"),
    "a slow-loop latency of 0": (edit(("/algorithms/0/params", {"slow_loop_latency": 0})),
                                 "/algorithms/0/params/slow_loop_latency"),
    "a signed-distance voxmap without proximity layers": (
        edit(("/algorithms/0", {"name": "voxmap_pointshell",
                                "params": {"variant": "signed_distance", "proximity_layers": 0}})),
        "/algorithms/0/params/proximity_layers"),
    "an unknown oracle": (edit(("/reference/oracle", "fcl")), "/reference/oracle"),
    "exact_every 0": (edit(("/reference/exact_every", 0)), "/reference/exact_every"),
    "a zero sample spacing": (edit(("/reference/sample_spacing_m", 0)),
                              "/reference/sample_spacing_m"),
    "an unknown device key": (edit(("/device/max_force", 20)), "/device"),
    "a zero force limit": (edit(("/device/max_force_n", 0)), "/device/max_force_n"),
    "gravity of 2 numbers": (edit(("/gravity", [0, -9.81])), "/gravity"),
    "an unknown closed_loop block": (edit(("/closed_loop", {"arm": {}})), "/closed_loop"),
    "a negative hand stiffness": (edit(("/closed_loop", {"hand": {"k_t": -1}})),
                                  "/closed_loop/hand/k_t"),
    "a zero device mass": (edit(("/closed_loop", {"device": {"mass_kg": 0}})),
                           "/closed_loop/device/mass_kg"),
    "an encoder finer than 1e-9 m": (edit(("/closed_loop", {"device": {"encoder_m": 1e-12}})),
                                     "/closed_loop/device/encoder_m"),
    "an empty reason in expected_unstable": (
        edit(("/expected_unstable", {"coupling_only": ""})), "/expected_unstable/coupling_only"),
    "a tag given twice": (edit(("/tags", ["stress", "stress"])), "/tags"),
    "a name with a space": (edit(("/name", "sphere press")), "/name"),
    "the name \"..\"": (edit(("/name", "..")), "/name"),
}

# Scenarios the reader accepts (the plugin's with --plugin), which the schema
# must accept too.
ACCEPTED = {
    "closed_loop with every default": edit(("/closed_loop", {})),
    "closed_loop settings": edit(("/closed_loop", {
        "hand": {"mass_kg": 0.1, "k_t": 300},
        "device": {"mass_kg": 0.05, "encoder_m": 0, "encoder_rad": 1e-6}})),
    "a measured slow-loop latency": edit(("/algorithms/0/params",
                                          {"slow_loop_latency": "measured"})),
    "a fixed slow-loop latency": edit(("/algorithms/1/params/slow_loop_latency", 3)),
    "a 3x3 inertia": edit(*MASS_NOT_DENSITY,
                          ("/tool/inertia", [[5e-6, 0, 0], [0, 5e-6, 0], [0, 0, 5e-6]])),
    "a diagonal inertia": edit(*MASS_NOT_DENSITY, ("/tool/inertia", [5e-6, 5e-6, 5e-6])),
    "a whole number written 2.0": edit(("/tool/shape/subdivisions", 2.0)),
    "a trace file with units": edit(("/trace", {"file": "traces/press_sphere.csv",
                                                "units": "m, s, rad", "duration_s": 1})),
    "a mesh tool": edit(("/tool", {"mesh": "models/bunny00.off", "scale": 0.02,
                                   "density": 1000})),
    "a capsule": edit(("/tool/shape", {"type": "capsule", "radius": 0.01, "length": 0.02})),
    "a box with a hole": edit(("/scene/0/shape", {"type": "box_with_hole",
                                                  "size": [0.4, 0.4, 0.02],
                                                  "hole_size": [0.01, 0.01]})),
    "a path of three waypoints": edit(("/trace", {
        "generator": "path", "duration_s": 2,
        "params": {"points": [0, 0, 0.03, 0.05, 0, 0.03, 0, 0, 0.03], "speed_mps": 0.2}})),
    "a repeated sample": edit(("/trace/params/repeat_sample_at_s", 0.5)),
    "every oracle": edit(("/reference/oracle", "all")),
    "a plugin's algorithm (run with --plugin) and its parameters": edit(
        ("/algorithms/0", {"name": "my_renderer", "params": {"gain": 2, "mode": "fast"}})),
    "expected_unstable": edit(("/expected_unstable", {"penalty_explicit": "explicit Euler"})),
    "tags": edit(("/tags", ["stress", "k_t=2000"])),
}


class VariantsTest(unittest.TestCase):
    def base(self):
        return load_json("scenarios", "smoke", "sphere_press_box.json")

    def test_the_base_scenario_validates(self):
        self.assertTrue(VALIDATOR.is_valid(self.base()))

    def test_what_the_reader_refuses_the_schema_refuses_there(self):
        for what, (change, pointer) in BROKEN.items():
            with self.subTest(what):
                errors = list(VALIDATOR.iter_errors(change(self.base())))
                self.assertTrue(errors, "the schema accepts it")
                pointers = error_pointers(errors)
                at = pointer.rstrip("/")
                self.assertTrue(any(p.rstrip("/") == at or (at and p.startswith(at + "/"))
                                    for p in pointers),
                                f"no error at or under {pointer}; "
                                f"errors at {sorted(set(pointers))}")

    def test_what_the_reader_accepts_the_schema_accepts(self):
        for what, change in ACCEPTED.items():
            with self.subTest(what):
                errors = VALIDATOR.iter_errors(change(self.base()))
                self.assertEqual([], ["/" + "/".join(map(str, e.absolute_path)) + ": " + e.message
                                      for e in errors])


class Reader:
    """The scenario reader's sources (harness/scenario/scenario.cpp, then
    scenario_*.cpp), split into ScenarioReader's read* methods."""

    DEFINITION = re.compile(r"^[A-Za-z][\w:<>, ]*?\bScenarioReader::(read\w*)\((?=[^;]*\{\s*$)",
                            re.M)

    def __init__(self):
        folder = os.path.join(ROOT, "harness", "scenario")
        names = ["scenario.cpp"] + sorted(
            os.path.basename(path) for path in glob.glob(os.path.join(folder, "scenario_*.cpp")))
        self.text = ""
        self.methods = {}
        for name in names:
            text = read_text("harness", "scenario", name)
            starts = [(m.start(), m.group(1)) for m in self.DEFINITION.finditer(text)]
            for i, (start, method) in enumerate(starts):
                end = starts[i + 1][0] if i + 1 < len(starts) else len(text)
                self.methods[method] = (len(self.text) + start, text[start:end])
            self.text += text

    def method(self, name):
        if name not in self.methods:
            raise AssertionError(f"the scenario reader has no method {name}() any more")
        return self.methods[name][1]

    @staticmethod
    def strings(braced):
        return re.findall(r'"([^"]*)"', braced)

    def method_at(self, offset):
        best = None
        for name, (start, body) in self.methods.items():
            if start <= offset < start + len(body):
                best = name
        return best


READER = Reader()


class ReaderKeysTest(unittest.TestCase):
    """Every reject_unknown_keys({...}) of the reader against the schema location
    it maps to: the same keys, and unknown ones refused there."""

    def shape_calls(self, body):
        types = Reader.strings(re.search(r"\.choice\((\{[^}]*\})\)", body).group(1))
        calls = {}
        for match in re.finditer(r"reject_unknown_keys\((\{[^}]*\})\)", body):
            before = body[:match.start()]
            branch = re.findall(r'type == "(\w+)"', before)
            last_test = max(m.start() for m in re.finditer(r'type == "\w+"', before))
            plain_else = [m.start() for m in re.finditer(r"\}\s*else\s*\{", before)]
            if plain_else and plain_else[-1] > last_test:
                rest = [t for t in types if t not in branch]
                self.assertEqual(1, len(rest), "read_shape's else branch is not the last type")
                calls[rest[0]] = Reader.strings(match.group(1))
            else:
                calls[branch[-1]] = Reader.strings(match.group(1))
        return types, calls

    def trace_calls(self, body):
        calls = {}
        for match in re.finditer(r"reject_unknown_keys\((\{[^}]*\})\)", body):
            before = body[:match.start()]
            in_else = before.rfind("} else {") > before.rfind("if (has_file)")
            calls["trace_generator" if in_else else "trace_file"] = Reader.strings(match.group(1))
        return calls

    def assert_keys(self, pointer, keys):
        node = resolve(pointer)
        self.assertEqual(sorted(keys), sorted(node["properties"]), pointer)
        self.assertIs(node.get("additionalProperties"), False, pointer)

    # method -> schema location of its one literal key list
    SINGLE = {
        "read": "#",
        "read_pose": "#/$defs/pose",
        "read_scene_object": "#/$defs/scene_object",
        "read_tool": "#/$defs/tool",
        "read_coupling": "#/properties/coupling",
        "read_device": "#/properties/device",
        "read_closed_loop": "#/properties/closed_loop",
        "read_algorithms": "#/$defs/algorithm",
        "read_reference": "#/properties/reference",
    }
    # reject_unknown_keys calls whose keys are not literal, checked below.
    COMPUTED = {"read_closed_loop", "read_budgets", "read_expected_unstable"}

    def test_every_literal_key_list_matches_its_schema_location(self):
        mapped = 0
        for match in re.finditer(r"reject_unknown_keys\(", READER.text):
            method = READER.method_at(match.start())
            literal = READER.text[match.end():].lstrip().startswith("{")
            with self.subTest(method=method):
                if method == "read_shape" or method == "read_trace":
                    continue  # one list per branch, below
                if not literal:
                    self.assertIn(method, self.COMPUTED,
                                  "a computed key list the test does not map")
                    continue
                self.assertIn(method, self.SINGLE, "a key list the test does not map to the schema")
                braced = re.match(r"\s*(\{[^}]*\})", READER.text[match.end():]).group(1)
                self.assert_keys(self.SINGLE[method], Reader.strings(braced))
                mapped += 1
        self.assertEqual(len(self.SINGLE), mapped)

    def test_shapes(self):
        types, calls = self.shape_calls(READER.method("read_shape"))
        self.assertEqual(sorted(types), sorted(calls))
        self.assertEqual(types, resolve("#/$defs/shape/properties/type")["enum"])
        for shape_type, keys in calls.items():
            with self.subTest(shape=shape_type):
                self.assert_keys(f"#/$defs/shape_{shape_type}", keys)

    def test_trace(self):
        calls = self.trace_calls(READER.method("read_trace"))
        self.assertEqual(["trace_file", "trace_generator"], sorted(calls))
        for location, keys in calls.items():
            with self.subTest(location):
                self.assert_keys(f"#/$defs/{location}", keys)
        body = READER.method("read_trace")
        formats = re.search(r'"format"\)\.choice\((\{[^}]*\})', body).group(1)
        self.assertEqual(Reader.strings(formats),
                         resolve("#/$defs/trace_file/properties/format")["enum"])

    def test_closed_loop_settings(self):
        body = READER.method("read_closed_loop")
        for block in ("hand", "device"):
            with self.subTest(block):
                settings = re.findall(r'\{"(\w+)", "[^"]*", &' + block + r'\.\w+, (true|false)\}',
                                      body)
                self.assertTrue(settings)
                node = resolve(f"#/$defs/closed_loop_{block}")
                self.assert_keys(f"#/$defs/closed_loop_{block}", [key for key, _ in settings])
                for key, positive in settings:
                    bound = node["properties"][key]
                    if positive == "true":
                        self.assertEqual(0, bound.get("exclusiveMinimum"), key)
                    elif "anyOf" not in bound:  # encoders: 0 or >= 1e-9
                        self.assertEqual(0, bound.get("minimum"), key)

    def test_budgets_are_the_metric_tables_budgets(self):
        self.assertIn("known_budget_names()", READER.method("read_budgets"))
        names = [row[0] for row in table_rows("docs/metric-table.md", 8)
                 if row[5].startswith("yes")]
        self.assertIn("tick_p99_us", names)
        self.assert_keys("#/properties/budgets", names)

    def test_expected_unstable_takes_any_label(self):
        node = resolve("#/properties/expected_unstable")
        self.assertEqual({"type": "string", "minLength": 1}, node["additionalProperties"])

    def test_required_keys(self):
        for method, variable, pointer in (("read", "root", "#"),
                                          ("read_algorithms", "entry", "#/$defs/algorithm")):
            with self.subTest(method):
                required = re.findall(variable + r'\.member\("(\w+)"', READER.method(method))
                self.assertEqual(sorted(required), sorted(resolve(pointer)["required"]))
        body = READER.method("read_trace")
        generator_branch = body[body.rfind("} else {"):]
        self.assertEqual(sorted(["generator"] + re.findall(r'field\.member\("(\w+)"',
                                                           generator_branch)),
                         sorted(resolve("#/$defs/trace_generator")["required"]))

    def test_reference_choices(self):
        body = READER.method("read_reference")
        for key in ("analytic", "force"):
            with self.subTest(key):
                choices = re.search(r'"' + key + r'"\)\.choice\((\{[^}]*\})', body).group(1)
                self.assertEqual(Reader.strings(choices),
                                 resolve(f"#/properties/reference/properties/{key}")["enum"])
        backends = re.findall(r'\{"(\w+)", &make_\w+_oracle', read_text("harness", "reference",
                                                                          "oracle.cpp"))
        self.assertTrue(backends)
        self.assertEqual(["none"] + backends + ["all", "both"],
                         resolve("#/properties/reference/properties/oracle")["enum"])


class ParametersTest(unittest.TestCase):
    """Algorithm and generator parameters against the tables `hapticbench list`
    prints (the C++ tests keep those tables equal to its output)."""

    def check_owner(self, owner, pointer, rows, extra):
        node = resolve(pointer)
        self.assertIs(node.get("additionalProperties"), False, pointer)
        self.assertEqual(sorted([row[1] for row in rows] + extra), sorted(node["properties"]))
        for row in rows:
            with self.subTest(owner=owner, parameter=row[1]):
                actual = constraints_of(node["properties"][row[1]])
                self.assertEqual(expected_constraints(owner, row[1], row[3]), actual)

    def test_algorithms(self):
        rows = table_rows("docs/algorithms/README.md", 4)
        names = list(dict.fromkeys(row[0] for row in rows))
        self.assertIn("god_object", names)
        name_node = resolve("#/$defs/algorithm/properties/name")
        self.assertEqual(names, name_node["anyOf"][0]["enum"])
        conditions = [rule["if"]["properties"]["name"]["const"]
                      for rule in resolve("#/$defs/algorithm")["allOf"]]
        self.assertEqual(names, conditions)
        for name in names:
            self.check_owner(name, f"#/$defs/algorithm_params_{name}",
                             [row for row in rows if row[0] == name], ["slow_loop_latency"])

    def test_slow_loop_latency(self):
        text = read_text("harness", "run", "prepare_scenario.cpp")
        match = re.search(r'integer_or_word\("slow_loop_latency", \w+, (\w+), (\w+), "(\w+)"\)',
                          text)
        self.assertIsNotNone(match, "prepare_scenario.cpp reads slow_loop_latency differently")
        whole, word = resolve("#/$defs/slow_loop_latency")["anyOf"]
        self.assertEqual((int(match.group(1)), int(match.group(2))),
                         (whole["minimum"], whole["maximum"]))
        self.assertEqual(match.group(3), word["const"])

    def test_generators(self):
        rows = [row for row in table_rows("traces/README.md", 4) if row[0] != "generator"]
        names = list(dict.fromkeys(row[0] for row in rows))
        self.assertIn("press", names)
        self.assertEqual(names, resolve("#/$defs/trace_generator/properties/generator")["enum"])
        self.assertIn('kRepeatSampleKey = "repeat_sample_at_s"',
                      read_text("harness", "trace", "generators.cpp"))
        for name in names:
            self.check_owner(name, f"#/$defs/generator_params_{name}",
                             [row for row in rows if row[0] == name], ["repeat_sample_at_s"])


if __name__ == "__main__":
    unittest.main()

"""The sections of the LaTeX derivation laid out: content (:mod:`symkin.kernels.document`) in,
:class:`Section` of LaTeX text out.

Each section is a heading, an introduction and a list of :class:`Quantity`: one display (or
table, or paragraph) that is also a snippet file and a macro of its own.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import sympy as sp

from symkin.emit.latex.layout import (
    Layout,
    MatrixItem,
    align,
    entry_name,
    vector_name,
)
from symkin.emit.latex.printer import KinematicsLatexPrinter
from symkin.kernels.document import (
    ALL_TASK_ROWS,
    DeterminantContent,
    DHContent,
    DocumentContent,
    DynamicsContent,
    FKContent,
    InverseContent,
    JacobianContent,
    Shown,
)

# The adjugate is printed when its entries fill at most this many lines.
INVERSE_MAX_LINES = 40
# Euler angles of this robot are printed in terms of q only when each fits on a line.
EULER_MARGIN_UNITS = 8.0
ROW_LATEX = {"x": "x", "y": "y", "z": "z", "wx": "\\omega_{x}", "wy": "\\omega_{y}"}
ROW_LATEX["wz"] = "\\omega_{z}"
DIGIT_WORDS = ("Zero", "One", "Two", "Three", "Four", "Five", "Six", "Seven", "Eight", "Nine")
# Dynamics terms by content key: macro, description, symbol.
DYNAMICS_TERMS = {
    "mass-matrix": ("MassMatrix", "the mass matrix", "M"),
    "coriolis-matrix": ("CoriolisMatrix", "the Coriolis matrix", "C"),
    "gravity-vector": ("GravityVector", "the gravity torques", "G"),
    "friction-vector": ("FrictionVector", "the friction torques", "F"),
    "wrench-torque": ("WrenchTorque", "the torques of an external wrench", r"\tau_{w}"),
    "potential-energy": ("PotentialEnergy", "the potential energy", "V"),
}


def number_words(i: int) -> str:
    """``12`` -> ``OneTwo``: a number in a macro name, which takes letters only."""
    return "".join(DIGIT_WORDS[int(c)] for c in str(i))


@dataclass(frozen=True)
class Quantity:
    """One displayed quantity: a snippet file, a macro and a part of a section."""

    key: str
    macro: str
    description: str
    body: str
    text: str = ""


@dataclass(frozen=True)
class Section:
    key: str
    heading: str
    intro: str
    quantities: tuple[Quantity, ...]


@dataclass
class SectionWriter:
    """Lays out the sections of ``content`` with ``layout`` and the prose ``t``."""

    content: DocumentContent
    layout: Layout
    t: Mapping[str, str]

    def build(self) -> list[Section]:
        """The sections asked for, in document order (a non-square Jacobian has no inverse)."""
        c = self.content
        builders: dict[str, Callable[[], Section | None]] = {
            "dh": lambda: self.section_dh(c.dh),
            "transforms": lambda: self.section_transforms(c.transforms),
            "fk": lambda: self.section_fk(c.fk),
            "euler": lambda: self.section_euler(c.euler),
            "jacobian": lambda: self.section_jacobian(c.jacobian),
            "det": lambda: self.section_det(c.det),
            "inverse": lambda: None if c.inverse is None else self.section_inverse(c.inverse),
            "dynamics": lambda: self.section_dynamics(c.dynamics),
        }
        # Imported here: the frame sections build on this module's Quantity and Section.
        from symkin.emit.latex.sections_frames import section_graph, section_points

        builders["graph"] = lambda: section_graph(c.graph, self.t)
        builders["points"] = lambda: section_points(self, c.points)
        sections = (builders[key]() for key in c.sections)
        return [section for section in sections if section is not None]

    def math(self, expr: sp.Expr) -> str:
        return f"${self.layout.tex(expr)}$"

    def display(
        self, lhs: str, shown: Shown, name: Callable[[int, int], str], *, list_named: bool = True
    ) -> str:
        """``lhs = [matrix]`` and its numbers at ``q*``, if any (see :meth:`Layout.displays`)."""
        return self.layout.matrix_display(
            lhs, shown.value, name, shown.numbers, where=self.t["where"], list_named=list_named
        )

    @property
    def task_symbol(self) -> str:
        if tuple(self.content.model.task_rows) == ALL_TASK_ROWS:
            return "J"
        return r"J_{\mathrm{task}}"

    # -- sections -------------------------------------------------------------------------

    def section_dh(self, dh: DHContent) -> Section:
        layout, t = self.layout, self.t
        convention = self.content.model.robot.convention
        product = {
            "standard": r"\mathrm{Rot}_{z}(\theta_{i})\, \mathrm{Trans}_{z}(d_{i})\, "
            r"\mathrm{Trans}_{x}(a_{i})\, \mathrm{Rot}_{x}(\alpha_{i})",
            "modified": r"\mathrm{Rot}_{x}(\alpha_{i-1})\, \mathrm{Trans}_{x}(a_{i-1})\, "
            r"\mathrm{Rot}_{z}(\theta_{i})\, \mathrm{Trans}_{z}(d_{i})",
            "placement": r"\mathrm{Rot}_{z}(\theta_{i})\, \mathrm{Trans}_{z}(d_{i})",
        }[convention]
        lhs = r"A_{i} = {}^{i-1}T_{i}"
        if convention == "placement":  # A_i = P_i Rz Tz, and the matrix shown is Rz Tz
            lhs, product = rf"{lhs} &= P_{{i}}\, {product} \\{product}", ""
        # The general matrix is printed without shorthand: its angles are theta_i, alpha_i.
        general_printer = KinematicsLatexPrinter((), fold_func_brackets=True)
        general_rows = [
            [general_printer.doprint(dh.general[j, k]) for k in range(4)] for j in range(4)
        ]
        matrix = layout.bmatrix(general_rows)
        formula = align(
            [rf"{lhs} &= {product} \\&= {matrix}" if product else rf"{lhs} &= {matrix}"]
        )
        table = self.placement_table(dh) if convention == "placement" else self.dh_table(dh)
        quantities = [
            Quantity("dh-matrix", "DHMatrix", "the general DH link transform", formula),
            Quantity("dh-table", "DHTable", "the DH table", table, text=t["table_intro"]),
            Quantity("parameters", "Parameters", "parameter values", self.parameter_text(dh)),
        ]
        for key, matrix in (("base", dh.base), ("tool", dh.tool)):
            if matrix is not None:
                symbol = r"T_{\mathrm{" + key + "}}"
                body = layout.matrix_display(
                    symbol, matrix, entry_name("b" if key == "base" else "e"), where=t["where"]
                )
                quantities.append(
                    Quantity(
                        f"{key}-transform", key.capitalize(), f"the {key} transform", body, t[key]
                    )
                )
        return Section("dh", t["dh"], t[f"dh_intro_{convention}"], tuple(quantities))

    def dh_table(self, dh: DHContent) -> str:
        """The DH table, columns in the order of the convention's product."""
        standard = self.content.model.robot.convention == "standard"
        if standard:
            columns = [r"\theta_{i}", "d_{i}", "a_{i}", r"\alpha_{i}"]
        else:
            columns = [r"\alpha_{i-1}", "a_{i-1}", r"\theta_{i}", "d_{i}"]
        rows = []
        for row in dh.rows:
            th, dd, aa, al = row.values
            rows.append([th, dd, aa, al] if standard else [al, aa, th, dd])
        return self.table([f"${c}$" for c in columns], dh, rows)

    def placement_table(self, dh: DHContent) -> str:
        """Placed joints: ``P_i`` as URDF's origin (xyz, fixed-axis rpy) and the motion."""
        names = ["x_{i}", "y_{i}", "z_{i}", r"\mathrm{roll}_{i}", r"\mathrm{pitch}_{i}"]
        columns = [f"${c}$" for c in [*names, r"\mathrm{yaw}_{i}"]]
        rows = []
        for row in dh.rows:
            theta, d, _, _ = row.values
            rows.append([*(sp.N(v, 6) for v in row.placement), theta, d])
        return self.table([*columns, r"$\theta_{i}$", "$d_{i}$"], dh, rows)

    def table(self, columns: list[str], dh: DHContent, rows: list[list[sp.Expr]]) -> str:
        t = self.t
        header = " & ".join([r"$i$", t["joint"], *columns])
        lines = [
            r"\begin{center}",
            r"\begin{tabular}{cl" + "c" * len(columns) + "}",
            r"\toprule",
            header + r" \\",
            r"\midrule",
        ]
        for index, (row, values) in enumerate(zip(dh.rows, rows, strict=True), start=1):
            cells = [f"${index}$", t[row.joint_type]] + [self.math(v) for v in values]
            lines.append(" & ".join(cells) + r" \\")
        lines += [r"\bottomrule", r"\end{tabular}", r"\end{center}"]
        return "\n".join(lines)

    def parameter_text(self, dh: DHContent) -> str:
        t = self.t
        if not dh.parameters:
            return t["no_parameters"]
        items = []
        for symbol, value in dh.parameters:
            name_tex = self.layout.tex(symbol)
            if value is None:
                items.append(f"${name_tex}$ ({t['no_value']})")
            else:
                items.append(f"${name_tex} = {self.layout.given_number(value)}$")
        separator = "; " if self.layout.decimal_comma else ", "
        return t["parameters"] + " " + separator.join(items) + "."

    def section_transforms(self, transforms: tuple[Shown, ...]) -> Section:
        quantities = []
        for i, shown in enumerate(transforms, start=1):
            lhs = rf"A_{{{i}}} = {{}}^{{{i - 1}}}T_{{{i}}}"
            quantities.append(
                Quantity(
                    f"link-transform-{i}",
                    f"LinkTransform{number_words(i)}",
                    f"A_{i}, the pose of frame {i} in frame {i - 1}",
                    self.display(lhs, shown, entry_name("a", f"^{{({i})}}")),
                )
            )
        t = self.t
        return Section("transforms", t["transforms"], t["transforms_intro"], tuple(quantities))

    def section_fk(self, fk: FKContent) -> Section:
        t = self.t
        n = len(fk.frames)
        quantities = []
        for i, shown in enumerate(fk.frames, start=1):
            last = i == n and fk.tool is None
            if i == 1:
                product = r"T_{\mathrm{base}}\, A_{1}" if fk.has_base else "A_{1}"
            else:
                product = rf"{{}}^{{0}}T_{{{i - 1}}}\, A_{{{i}}}"
            if i == 1 and not fk.has_base and not last:
                body = align([r"{}^{0}T_{1} &= A_{1}"])
            elif last:
                body = self.display(rf"T = {{}}^{{0}}T_{{{i}}} = {product}", shown, entry_name("T"))
            else:
                lhs = rf"{{}}^{{0}}T_{{{i}}} = {product}"
                body = self.display(lhs, shown, entry_name("t", f"^{{({i})}}"))
            if last:
                quantities.append(self.forward_kinematics(body))
            else:
                quantities.append(
                    Quantity(
                        f"frame-transform-{i}",
                        f"FrameTransform{number_words(i)}",
                        f"T_0_{i}, the pose of frame {i} in the base frame",
                        body,
                    )
                )
        if fk.tool is not None:
            lhs = rf"T = {{}}^{{0}}T_{{{n}}}\, T_{{\mathrm{{tool}}}}"
            quantities.append(self.forward_kinematics(self.display(lhs, fk.tool, entry_name("T"))))
        body = self.display(
            r"p = \begin{bmatrix} x \\ y \\ z \end{bmatrix}", fk.position, vector_name("p", "xyz")
        )
        quantities.append(
            Quantity(
                "tool-position", "ToolPosition", "p, the tool position", body, t["tool_position"]
            )
        )
        return Section("fk", t["fk"], t["fk_intro"], tuple(quantities))

    @staticmethod
    def forward_kinematics(body: str) -> Quantity:
        return Quantity(
            "forward-kinematics",
            "ForwardKinematics",
            "T, the pose of the tool in the base frame",
            body,
        )

    def section_euler(self, angles: tuple[Shown, ...]) -> Section:
        layout, t = self.layout, self.t
        general = align(
            [
                r"\psi &= \operatorname{atan2}\left(r_{21}, r_{11}\right)",
                r"\theta &= \operatorname{atan2}\left(-r_{31}, "
                r"\sqrt{r_{11}^{2} + r_{21}^{2}}\right)",
                r"\varphi &= \operatorname{atan2}\left(r_{32}, r_{33}\right)",
            ]
        )
        names = (r"\psi", r"\theta", r"\varphi")
        if all(layout.measure(a.value) <= layout.width - EULER_MARGIN_UNITS for a in angles):
            rows = []
            for symbol, angle in zip(names, angles, strict=True):
                value = None if angle.value.is_number else angle.numbers
                rows += layout.equation_rows(symbol, angle.value, value)
            body, text = align(rows), t["euler_singular"] + " " + t["euler_robot"]
        else:
            body, text = "", t["euler_singular"] + " " + t["euler_long"]
            if self.content.q is not None:
                rows = [
                    f"{s}(q^{{*}}) &= {layout.number(a.numbers)}"
                    for s, a in zip(names, angles, strict=True)
                ]
                body = align(rows)
        quantities = [
            Quantity("euler-zyx-formulas", "EulerFormulas", "the Z-Y-X Euler formulas", general),
            Quantity("euler-zyx", "EulerZYX", "the Z-Y-X Euler angles of this robot", body, text),
        ]
        return Section("euler", t["euler"], t["euler_intro"], tuple(quantities))

    def section_jacobian(self, jc: JacobianContent) -> Section:
        layout, t = self.layout, self.t
        robot = self.content.model.robot
        k = "i-1" if robot.convention == "standard" else "i"
        formula = align(
            [
                rf"J_{{i}} &= \begin{{bmatrix}} z_{{{k}}} \times (p - o_{{{k}}}) \\ z_{{{k}}}"
                rf"\end{{bmatrix}} \qquad \text{{({t['revolute']})}}",
                rf"J_{{i}} &= \begin{{bmatrix}} z_{{{k}}} \\ 0 \end{{bmatrix}} "
                rf"\qquad \text{{({t['prismatic']})}}",
            ]
        )
        quantities = [Quantity("jacobian-formula", "JacobianFormula", "Jacobian columns", formula)]
        for i, column in enumerate(jc.columns, start=1):
            f = column.frame
            items: list[MatrixItem] = [
                (f"z_{{{f}}}", column.axis, vector_name("z", "xyz", str(f)), None)
            ]
            if column.joint_type == "revolute":
                items.append((f"o_{{{f}}}", column.origin, vector_name("o", "xyz", str(f)), None))
            items.append(
                (
                    f"J_{{{i}}}",
                    column.column.value,
                    lambda j, _, i=i: f"J_{{{j + 1}{i}}}",
                    column.column.numbers,
                )
            )
            quantities.append(
                Quantity(
                    f"jacobian-column-{i}",
                    f"JacobianColumn{number_words(i)}",
                    f"column {i} of the geometric Jacobian",
                    layout.displays(items, where=t["where"]),
                    t["column"].format(i=i, kind=t[column.joint_type]),
                )
            )
        body = self.display("J", jc.jacobian, entry_name("J"), list_named=False)
        if not layout.fits("J", jc.jacobian.value):
            body += "\n" + t["jacobian_names"]
        quantities.append(
            Quantity("jacobian", "Jacobian", "the geometric Jacobian", body, t["jacobian_full"])
        )
        if jc.task is not None:
            names = ", ".join(f"${ROW_LATEX[r]}$" for r in self.content.model.task_rows)
            body = self.display(r"J_{\mathrm{task}}", jc.task, entry_name("J"), list_named=False)
            quantities.append(
                Quantity(
                    "task-jacobian",
                    "TaskJacobian",
                    "the task Jacobian",
                    body,
                    t["task"].format(rows=names),
                )
            )
        intro = t["jacobian_intro"].format(dof=robot.dof, k=k)
        return Section("jacobian", t["jacobian"], intro, tuple(quantities))

    def section_det(self, det: DeterminantContent | None) -> Section:
        layout, t = self.layout, self.t
        if det is None:
            return Section("det", t["det"], t["det_none"], ())
        if det.determinant is None:
            return Section("det", t["det"], t["det_missing"], ())
        determinant = det.determinant
        body = align(
            layout.equation_rows(
                rf"\det {self.task_symbol}", determinant.value, determinant.numbers
            )
        )
        quantities = [Quantity("determinant", "Determinant", "the factored determinant", body)]
        if det.singular:
            rows = [layout.equation_rows(layout.tex(c.lhs), c.rhs)[0] for c in det.singular]
            rows = [
                row + (rf" \qquad \text{{{t['or']}}}" if n < len(rows) - 1 else "")
                for n, row in enumerate(rows)
            ]
            body, text = align(rows), t["singular"]
        else:
            body, text = t["singular_none"], ""
        quantities.append(
            Quantity("singularities", "Singularities", "the singular configurations", body, text)
        )
        return Section("det", t["det"], t["det_intro"], tuple(quantities))

    def section_inverse(self, inverse: InverseContent) -> Section:
        layout, t = self.layout, self.t
        n = self.content.model.robot.dof
        symbol = self.task_symbol
        adjugate = inverse.adjugate
        body = ""
        if (
            adjugate is not None
            and sum(layout.measure(e) for e in adjugate) <= INVERSE_MAX_LINES * layout.width
        ):
            formula = rf"{symbol}^{{-1}} &= \frac{{\operatorname{{adj}} {symbol}}}{{\det {symbol}}}"
            adj = rf"\operatorname{{adj}} {symbol}"
            display = layout.matrix_display(
                adj, adjugate, entry_name(r"\tilde{J}"), where=t["where"]
            )
            body = align([formula]) + "\n" + display
        if not body:
            body = t["inverse_long"].format(dof=n, m=n - 1)
        if self.content.q is not None:
            if inverse.numbers is None:
                body += "\n" + t["inverse_singular"]
            else:
                body += "\n" + align(
                    [rf"{symbol}^{{-1}}(q^{{*}}) &= {layout.numeric_matrix(inverse.numbers)}"]
                )
        quantity = Quantity("inverse-jacobian", "InverseJacobian", "the inverse Jacobian", body)
        return Section("inverse", t["inverse"], t["inverse_intro"], (quantity,))

    def wrench_and_energies(self) -> Quantity:
        """``tau`` with the external wrench, the statics and ``T``, ``V``, ``L`` (general)."""
        body = align(
            [
                r"\tau &= M(q)\, \ddot{q} + C(q, \dot{q})\, \dot{q} + G(q) + F(\dot{q}) - J^{T} w, "
                r"\qquad \tau_{s} = G(q) - J^{T} w",
                r"T &= \frac{1}{2} \dot{q}^{T} M(q)\, \dot{q}, \qquad "
                r"V = -\sum_{i=1}^{n} m_{i}\, g^{T} r_{c,i}, \qquad L = T - V",
            ]
        )
        return Quantity(
            "wrench-energies",
            "WrenchEnergies",
            "the external wrench and the energies",
            body,
            self.t["dynamics_wrench_energies"],
        )

    def section_dynamics(self, dynamics: DynamicsContent) -> Section:
        t = self.t
        n = self.content.model.robot.dof
        lagrange = align(
            [
                r"M(q) &= \sum_{i=1}^{n} \left( m_{i}\, J_{v,i}^{T} J_{v,i} + J_{\omega,i}^{T} "
                r"R_{i} I_{i} R_{i}^{T} J_{\omega,i} \right)"
                + (r" + \operatorname{diag}(I_{a,i})" if dynamics.rotors else ""),
                r"G(q) &= \frac{\partial P}{\partial q}, \qquad "
                r"P = -\sum_{i=1}^{n} m_{i}\, g^{T} r_{c,i}",
            ]
        )
        christoffel = align(
            [
                r"C_{kj} &= \sum_{i=1}^{n} \frac{1}{2} \left( "
                r"\frac{\partial M_{kj}}{\partial q_{i}} + \frac{\partial M_{ki}}{\partial q_{j}}"
                r" - \frac{\partial M_{ij}}{\partial q_{k}} \right) \dot{q}_{i}"
            ]
        )
        quantities = [
            Quantity("lagrange", "Lagrange", "M and G by Lagrange", lagrange),
            Quantity(
                "christoffel", "Christoffel", "C from M", christoffel, t["dynamics_christoffel"]
            ),
            self.wrench_and_energies(),
        ]
        # Without terms (beyond READABLE_DOF joints) the section says how the generated code
        # computes them.
        if not dynamics.terms:
            long = t["dynamics_long"].format(dof=n)
            quantities.append(
                Quantity("dynamics-long", "DynamicsLong", "where the equations of motion are", long)
            )
        quantities += self._elastic_joints()
        rows = [str(i) for i in range(1, n + 1)]
        for key, shown in dynamics.terms:
            macro, description, symbol = DYNAMICS_TERMS[key]
            if isinstance(shown.value, sp.MatrixBase):
                cols = shown.value.cols
                name = entry_name(symbol) if cols > 1 else vector_name(symbol, rows)
                body = self.display(symbol, shown, name)
            else:  # a scalar: the potential energy
                value = None if shown.numbers is None else float(shown.numbers)
                body = align(self.layout.equation_rows(symbol, shown.value, value))
            text = t[key.replace("-", "_")]
            quantities.append(Quantity(key, macro, description, body, text))
        return Section("dynamics", t["dynamics"], t["dynamics_intro"], tuple(quantities))

    def _elastic_joints(self) -> list[Quantity]:
        """Spong's reduced model and its motor-side inverse dynamics, for a robot with
        elastic joints (none otherwise); the stiffnesses and motor inertias as diagonals."""
        robot = self.content.model.robot
        if not robot.elastic_joints:
            return []
        links = [robot.joints[i].link for i in robot.elastic_joints]
        stiffness = ", ".join(self.layout.tex(link.stiffness) for link in links)  # type: ignore[union-attr]
        inertia = ", ".join(self.layout.tex(link.motor_inertia) for link in links)  # type: ignore[union-attr]
        body = align(
            [
                r"M(q)\, \ddot{q} + C(q, \dot{q})\, \dot{q} + G(q) + F(\dot{q}) &= K (\theta - q)",
                r"B\, \ddot{\theta} + K (\theta - q) &= \tau_{m}",
                r"\theta &= q + K^{-1} \tau_{l}",
                r"\tau_{m} &= B \left( \ddot{q} + K^{-1} \ddot{\tau}_{l} \right) + \tau_{l}",
                rf"K &= \operatorname{{diag}}({stiffness}), \qquad "
                rf"B = \operatorname{{diag}}({inertia})",
            ]
        )
        joints = ", ".join(str(i + 1) for i in robot.elastic_joints)
        text = self.t["dynamics_elastic"].format(joints=joints)
        return [Quantity("elastic-joints", "ElasticJoints", "the elastic joints", body, text)]

"""Shader nodes -> weighted terms: each BSDF node a closure (a restircl.Material without layers), each emitter an
emission, with the weight that the Mix and Add Shaders above it give it. material.py folds the terms into one
Material."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .inputs import InputReader
from .nodes import NodeLoop, default_float, find_input, resolve
from .notes import Notes

# Principled inputs that switch on a lobe we do not render: (names across Blender versions, lobe, its "off" value)
PRINCIPLED_LOBES = (
    (("Subsurface Weight", "Subsurface"), "subsurface", 0.0),
    (("Coat Weight", "Coat", "Clearcoat"), "coat", 0.0),
    (("Sheen Weight", "Sheen"), "sheen", 0.0),
    (("Anisotropic",), "anisotropy", 0.0),
    (("Diffuse Roughness",), "diffuse roughness", 0.0),
)
GLOSSY_NODES = ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic")
# the dielectric BSDFs (opencl/bsdf/microfacet_dielectric.h): node -> Material.kind
DIELECTRIC_NODES = {"ShaderNodeBsdfGlass": "glass", "ShaderNodeBsdfRefraction": "refraction"}
# BSDFs we do not have, rendered as a diffuse of their colour (the nearest look under direct light)
AS_DIFFUSE = ("ShaderNodeSubsurfaceScattering", "ShaderNodeBsdfToon", "ShaderNodeBsdfSheen",
              "ShaderNodeBsdfTranslucent")
DISTRIBUTIONS = {"MULTI_GGX": "multi_ggx", "GGX": "ggx"}


@dataclass
class Weight:
    """c * f (or c * (1 - f) when `invert`), f a texture factor of one Mix Shader or None (f = 1)."""

    c: float = 1.0
    factor: object = None
    invert: bool = False

    def scaled(self, c: float) -> Weight:
        return Weight(self.c * c, self.factor, self.invert)


@dataclass
class Term:
    weight: Weight
    label: str
    closure: object = None  # restircl.Material (kind, albedo, ...) or None for an emission
    emission: object = None  # colour Input
    strength: float = 0.0
    transparent: object = None  # a Transparent BSDF's colour (rgb), layers.py folds it into the coverage


class ShaderReader:
    def __init__(self, inputs: InputReader, notes: Notes):
        self.inputs = inputs
        self.notes = notes

    def terms(self, socket) -> list[Term]:
        return self._shader(socket, (), Weight(), 0)

    def _shader(self, socket, stack: tuple, w: Weight, depth: int) -> list[Term]:
        try:
            src = resolve(socket, stack)
        except NodeLoop:
            self.notes.note("the shader graph links back into itself (a node loop); that branch is left out")
            return []
        if not src.linked or depth > 32:
            return []
        node, kind = src.node, src.kind
        if node.mute:
            return []
        label = f"{node.bl_label} {node.name!r}"
        if src.socket.type != "SHADER":  # Cycles takes a colour linked to a shader socket as an emission
            return [Term(w, label, emission=self.inputs.color(socket, stack), strength=1.0)]
        if kind == "ShaderNodeAddShader":
            a, b = (s for s in node.inputs if s.type == "SHADER")
            return self._shader(a, src.stack, w, depth + 1) + self._shader(b, src.stack, w, depth + 1)
        if kind == "ShaderNodeMixShader":
            return self._mix(node, src.stack, w, depth)
        if kind == "ShaderNodeEmission":
            strength = self.inputs.constant(find_input(node, ("Strength",)), src.stack, f"{label} Strength")
            if strength < 0:
                self.notes.note(f"{label}: negative emission strength (subtracted light) is left out")
                return []
            return [Term(w, label, emission=self.inputs.color(find_input(node, ("Color",)), src.stack),
                         strength=strength)]
        if kind == "ShaderNodeBsdfPrincipled":
            return self._principled(node, src.stack, w, label)
        if kind == "ShaderNodeBsdfTransparent":
            colour = self.inputs.color(find_input(node, ("Color",)), src.stack)
            if not isinstance(colour, tuple):
                self.notes.note(f"{label}: a textured Transparent colour is taken as white")
                colour = (1.0, 1.0, 1.0)
            return [Term(w, label, transparent=colour)]
        closure = self._bsdf(node, src.stack, label)
        return [] if closure is None else [Term(w, label, closure=closure)]

    def _mix(self, node, stack: tuple, w: Weight, depth: int) -> list[Term]:
        a, b = (s for s in node.inputs if s.type == "SHADER")
        f = self.inputs.value(find_input(node, ("Fac", "Factor")), stack)
        if isinstance(f, float):
            f = min(max(f, 0.0), 1.0)
            wa, wb = w.scaled(1.0 - f), w.scaled(f)
        elif w.factor is None:
            wa, wb = Weight(w.c, f, True), Weight(w.c, f, False)
        else:
            self.notes.note(f"Mix Shader {node.name!r}: a texture factor under another texture-driven Mix Shader "
                            "is taken as 0.5")
            wa, wb = w.scaled(0.5), w.scaled(0.5)
        return self._shader(a, stack, wa, depth + 1) + self._shader(b, stack, wb, depth + 1)

    def _lobes_off(self, node, stack: tuple, label: str, lobes) -> None:
        for names, lobe, off in lobes:
            sock = find_input(node, names)
            if sock is None:
                continue
            try:
                src = resolve(sock, stack)
            except NodeLoop:
                continue
            if src.linked or abs(default_float(src.socket) - off) > 1e-6:
                self.notes.lobe(f"{lobe} ({label})")

    def _common(self, node, stack: tuple, label: str, **fields) -> object:
        import restircl

        inp = self.inputs
        rough = find_input(node, ("Roughness",))
        return restircl.Material(
            name=node.name, roughness=inp.unit(rough, stack, f"{label} Roughness") if rough is not None else 0.5,
            normal=inp.normal(find_input(node, ("Normal",)), stack, f"{label} Normal"), **fields)

    def _distribution(self, node, label: str) -> str:
        d = getattr(node, "distribution", "MULTI_GGX")
        if d not in DISTRIBUTIONS:
            self.notes.note(f"{label}: distribution {d} is not supported; GGX is used")
        return DISTRIBUTIONS.get(d, "ggx")

    def _ior(self, node, stack: tuple, label: str) -> float:
        ior = self.inputs.constant(find_input(node, ("IOR",)), stack, f"{label} IOR")
        if not math.isfinite(ior) or ior <= 0:
            self.notes.note(f"{label}: IOR {ior:g} is not a refractive index; 1 (no specular reflection) is used")
            return 1.0
        return ior

    def _principled(self, node, stack: tuple, w: Weight, label: str) -> list[Term]:
        inp = self.inputs
        self._lobes_off(node, stack, label, PRINCIPLED_LOBES)
        closure = self._common(
            node, stack, label, kind="principled", albedo=inp.color(find_input(node, ("Base Color",)), stack),
            metallic=inp.unit(find_input(node, ("Metallic",)), stack, f"{label} Metallic"),
            ior=self._ior(node, stack, label),
            specular=inp.unit(find_input(node, ("Specular IOR Level", "Specular")), stack,
                              f"{label} Specular IOR Level"),
            specular_tint=inp.color(find_input(node, ("Specular Tint",)), stack),
            distribution=self._distribution(node, label), transmission=self._transmission(node, stack, label),
            thin_wall=self._thin_wall(node, stack, label), **self._thin_film(node, stack, label))
        from restircl.materials.textures import constant_float, is_texture
        from restircl.materials.thin_film import has_film

        metallic = 0.5 if is_texture(closure.metallic) else constant_float(closure.metallic)
        if has_film(closure) and closure.transmission > 0 and 0 < metallic < 1:
            self.notes.note(f"{label}: a thin film on a part-metallic BSDF with transmission makes more lobes than "
                            "a material holds; its transmission is left out")
        if has_film(closure) and closure.thin_wall and closure.transmission > 0:  # one resolve path has no sheet
            self.notes.note(f"{label}: a thin film on a Thin Wall is left out (the sheet is rendered without it)")
            closure.thin_film_thickness = 0.0
        alpha = find_input(node, ("Alpha",))
        if alpha is not None:
            closure.alpha = inp.unit(alpha, stack, f"{label} Alpha")
        terms = [Term(w, label, closure=closure)]
        if isinstance(closure.alpha, float):  # Cycles scales the emission by the Alpha too
            w = w.scaled(closure.alpha)
        strength_in = find_input(node, ("Emission Strength",))
        strength = inp.constant(strength_in, stack, f"{label} Emission Strength") if strength_in else 0.0
        if strength < 0:
            self.notes.note(f"{label}: negative emission strength (subtracted light) is left out")
        if strength > 0:
            colour = inp.color(find_input(node, ("Emission Color", "Emission")), stack)
            if not isinstance(colour, tuple) or max(colour) > 0:
                terms.append(Term(w, label, emission=colour, strength=strength))
        return terms

    def _transmission(self, node, stack: tuple, label: str) -> float:
        """The Principled BSDF's Transmission Weight, a constant in [0, 1] (a texture on it is taken as its default)."""
        sock = find_input(node, ("Transmission Weight", "Transmission"))
        if sock is None:
            return 0.0
        t = self.inputs.constant(sock, stack, f"{label} Transmission Weight")
        return min(max(t, 0.0), 1.0) if math.isfinite(t) else 0.0

    def _thin_wall(self, node, stack: tuple, label: str) -> bool:
        """Blender 5.3's Principled Thin Wall (opencl/bsdf/closures/thin_wall.h); a linked one is taken as its
        default. Cycles' thin-walled subsurface (a diffuse and a translucent lobe) is not modelled: subsurface stays
        in the lobes left out (PRINCIPLED_LOBES)."""
        sock = find_input(node, ("Thin Wall",))
        if sock is None:
            return False
        try:
            src = resolve(sock, stack)
        except NodeLoop:
            return False
        if src.linked:  # the input's own value, not the node's that it is linked to
            self.notes.note(f"{label}: a linked Thin Wall is taken as its default value")
            return bool(sock.default_value)
        return bool(src.socket.default_value)
    def _thin_film(self, node, stack: tuple, label: str) -> dict:
        """Thin Film Thickness (nm) and IOR as Material fields (none where the node has no film inputs), constants:
        a texture on either is taken as its default value, with a note."""
        from restircl.materials.thin_film import DEFAULT_IOR

        sock = find_input(node, ("Thin Film Thickness",))
        if sock is None:
            return {}
        thickness = self.inputs.constant(sock, stack, f"{label} Thin Film Thickness")
        ior_in = find_input(node, ("Thin Film IOR",))
        ior = self.inputs.constant(ior_in, stack, f"{label} Thin Film IOR") if ior_in is not None else DEFAULT_IOR
        if not (math.isfinite(thickness) and math.isfinite(ior)):
            self.notes.note(f"{label}: a thin film of thickness {thickness:g} and IOR {ior:g} is left out")
            return {}
        return {"thin_film_thickness": max(thickness, 0.0), "thin_film_ior": max(ior, 1e-5)}

    def _dielectric(self, node, stack: tuple, label: str, kind: str):
        dist = self._distribution(node, label)
        return self._common(node, stack, label, kind=kind, albedo=self.inputs.color(find_input(node, ("Color",)),
                                                                                    stack),
                            ior=self._ior(node, stack, label), distribution=dist,
                            **(self._thin_film(node, stack, label) if kind == "glass" else {}))

    def _bsdf(self, node, stack: tuple, label: str):
        inp, kind = self.inputs, node.bl_idname
        if kind in DIELECTRIC_NODES:
            return self._dielectric(node, stack, label, DIELECTRIC_NODES[kind])
        if kind == "ShaderNodeBsdfDiffuse":
            self._lobes_off(node, stack, label, ((("Roughness",), "Oren-Nayar roughness", 0.0),))
            return self._common(node, stack, label, kind="diffuse",
                                albedo=inp.color(find_input(node, ("Color",)), stack))
        if kind in GLOSSY_NODES:
            self._lobes_off(node, stack, label, ((("Anisotropy",), "anisotropy", 0.0),))
            return self._common(node, stack, label, kind="glossy",
                                albedo=inp.color(find_input(node, ("Color",)), stack),
                                distribution=self._distribution(node, label))
        if kind == "ShaderNodeBsdfMetallic":  # Blender 5's metal node: Principled's metal with F82 tint
            self._lobes_off(node, stack, label, ((("Anisotropy",), "anisotropy", 0.0),))
            if getattr(node, "fresnel_type", "F82") != "F82":
                self.notes.note(f"{label}: the physical conductor Fresnel is not supported; F82 tint is used")
            return self._common(node, stack, label, kind="principled", metallic=1.0,
                                albedo=inp.color(find_input(node, ("Base Color",)), stack),
                                specular_tint=inp.color(find_input(node, ("Edge Tint",)), stack),
                                distribution=self._distribution(node, label), **self._thin_film(node, stack, label))
        colour = find_input(node, ("Color", "Base Color"))
        if kind in AS_DIFFUSE and colour is not None:
            self.notes.note(f"{label} is not supported; rendered as a diffuse of its colour")
            import restircl

            return restircl.Material(name=node.name, kind="diffuse", albedo=inp.color(colour, stack))
        self.notes.lobe(label)
        return None

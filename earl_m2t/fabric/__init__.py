"""FABRIC packages (``spec/subsystem.xml`` + ``config/*.xml``) read into an EARL model:
``earl-m2t import fabric`` (docs/fabric-import.md)."""

from earl_m2t.fabric.package import FabricPackage, read_package
from earl_m2t.fabric.to_model import packages_to_model

__all__ = ["FabricPackage", "packages_to_model", "read_package"]

"""Where the tests find Orocos RTT and OCL's deployer, building them once when needed.

An installation is taken from, in order:
1. ``OROCOS_RTT_PREFIX`` (a prefix holding RTT and OCL's deployer, e.g. from a distribution);
2. the build cache: ``${XDG_CACHE_HOME:-~/.cache}/earl-m2t/orocos/<key>``, where ``<key>`` hashes
   the vendored sources and build script in ``../shared/vendor/orocos`` with the compiler and
   Boost versions the build used;
3. ``pkg-config orocos-rtt-gnulinux`` when its prefix also holds the deployer.
Otherwise ``ensure`` builds the vendored sources into the cache (``./dev test`` runs it before
the tests). A failed build leaves ``<key>.failed`` with the log's tail, which the Orocos tests
report as their failure instead of skipping.

Run as a script (standard library only, so it works before the test environment exists):
``python3 tests/support/orocos.py ensure`` prints the prefix, or the failure, and what it did.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
VENDOR = ROOT.parent / "shared" / "vendor" / "orocos"
BOOST_VERSION_HEADER = Path("/usr/include/boost/version.hpp")
LOG_TAIL_LINES = 40


class OrocosUnavailable(Exception):
    """No usable installation, and none can be built here; the message says why in one line."""


class OrocosBuildFailed(Exception):
    """The vendored sources did not build; the message holds the log's tail."""


@dataclass(frozen=True)
class Installation:
    prefix: Path
    origin: str  # "OROCOS_RTT_PREFIX", "cache" or "pkg-config"

    @property
    def deployer(self) -> Path:
        return self.prefix / "bin" / "deployer-gnulinux"

    def environment(self, component_path: list[Path]) -> dict[str, str]:
        """The environment a generated project is built and deployed with."""
        env = dict(os.environ)
        env["CMAKE_PREFIX_PATH"] = str(self.prefix)
        env["PKG_CONFIG_PATH"] = ":".join(filter(None, [str(self.prefix / "lib" / "pkgconfig"),
                                                         env.get("PKG_CONFIG_PATH", "")]))
        env["OROCOS_TARGET"] = "gnulinux"
        env["RTT_COMPONENT_PATH"] = ":".join(str(p) for p in [*component_path, self.prefix / "lib" / "orocos"])
        env["LD_LIBRARY_PATH"] = ":".join(filter(None, [str(self.prefix / "lib"), env.get("LD_LIBRARY_PATH", "")]))
        env["PATH"] = f"{self.prefix / 'bin'}:{env.get('PATH', '')}"
        return env


def built_project(source: Path, rtt: Installation, *flags: str) -> Path:
    """A generated Orocos project (``source``) configured against ``rtt`` (``flags`` as its C++
    flags), built and installed, once per content (tests/support/build_cache.py): the folder
    holding ``build/``, ``install/`` (with ``lib/orocos``) and ``build.log``, the output of the
    three commands, for the checks of compiler warnings."""
    from tests.support import build_cache

    configure = [f"-DCMAKE_PREFIX_PATH={rtt.prefix}", "-DCMAKE_CXX_FLAGS=" + " ".join(flags)]

    def build_and_install(folder: Path) -> None:
        output = []
        for command in (["cmake", "-S", str(folder / build_cache.SOURCE), "-B", str(folder / "build"), *configure],
                        ["cmake", "--build", str(folder / "build"), "-j", str(os.cpu_count() or 2)],
                        ["cmake", "--install", str(folder / "build"), "--prefix", str(folder / "install")]):
            result = subprocess.run(command, capture_output=True, text=True, timeout=900, env=rtt.environment([]))
            output.append(result.stdout + result.stderr)
            assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-4000:]
        (folder / "build.log").write_text("".join(output))

    return build_cache.built("orocos", source, build_and_install, ["cmake", *configure])


def is_usable(prefix: Path) -> bool:
    """RTT's pkg-config file and OCL's deployer are both there."""
    return ((prefix / "lib" / "pkgconfig" / "orocos-rtt-gnulinux.pc").is_file()
            and (prefix / "bin" / "deployer-gnulinux").is_file())


def cache_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "earl-m2t" / "orocos"


# Optimised as distributions ship RTT, so that the deployment tests and bench/latency.py run the
# RTT a robot runs: the build script's default, -O0, compiles a minute faster, but an unoptimised
# RTT adds its own cost to every wake-up the bench compares with hand-written code.
OPTIMISATION = "-O2 -g0"


def vendored_files() -> list[Path]:
    return sorted([*VENDOR.glob("*.tar.gz"), VENDOR / "build.sh"])


def toolchain_versions() -> str:
    """What a cached build depends on besides its sources: g++ and Boost (the libraries it links)."""
    compiler = subprocess.run(["g++", "-dumpfullversion"], capture_output=True, text=True).stdout.strip() \
        if shutil.which("g++") else "none"
    boost = "none"
    if BOOST_VERSION_HEADER.is_file():
        found = re.search(r'#define BOOST_LIB_VERSION "([^"]+)"', BOOST_VERSION_HEADER.read_text())
        boost = found.group(1) if found else "unknown"
    return f"g++ {compiler}; boost {boost}; {OPTIMISATION}"


def cache_key() -> str:
    digest = hashlib.sha256()
    for file in vendored_files():
        digest.update(file.name.encode() + b"\0" + hashlib.sha256(file.read_bytes()).digest())
    digest.update(toolchain_versions().encode())
    return digest.hexdigest()[:16]


def cached_prefix() -> Path:
    return cache_root() / cache_key()


def failure_marker(prefix: Path) -> Path:
    return prefix.with_name(prefix.name + ".failed")


def complete_stamp(prefix: Path) -> Path:
    return prefix / ".earl-m2t-complete"


def pkg_config_prefix() -> Path | None:
    if shutil.which("pkg-config") is None:
        return None
    result = subprocess.run(["pkg-config", "--variable=prefix", "orocos-rtt-gnulinux"], capture_output=True,
                            text=True)
    return Path(result.stdout.strip()) if result.returncode == 0 and result.stdout.strip() else None


def find() -> Installation | None:
    """A usable installation that is already there, without building anything."""
    explicit = os.environ.get("OROCOS_RTT_PREFIX")
    if explicit:
        if not is_usable(Path(explicit)):
            raise OrocosUnavailable(f"OROCOS_RTT_PREFIX={explicit} holds no RTT (lib/pkgconfig/"
                                    "orocos-rtt-gnulinux.pc) or no OCL deployer (bin/deployer-gnulinux)")
        return Installation(Path(explicit), "OROCOS_RTT_PREFIX")
    if VENDOR.is_dir():
        prefix = cached_prefix()
        if complete_stamp(prefix).is_file() and is_usable(prefix):
            return Installation(prefix, "cache")
    system = pkg_config_prefix()
    if system is not None and is_usable(system):
        return Installation(system, "pkg-config")
    return None


def installation() -> Installation:
    """What the Orocos tests run against; raises when there is none (never builds)."""
    found = find()
    if found is not None:
        return found
    if not VENDOR.is_dir():
        raise OrocosUnavailable("no Orocos RTT installation and no ../shared/vendor/orocos to build one from "
                                "(set OROCOS_RTT_PREFIX; see docs/orocos-target.md)")
    marker = failure_marker(cached_prefix())
    if marker.is_file():
        raise OrocosBuildFailed(marker.read_text())
    raise OrocosBuildFailed(f"Orocos RTT/OCL not built yet into {cached_prefix()}: run ./dev test, or "
                            "python3 tests/support/orocos.py ensure")


def log(message: str) -> None:
    print(f"earl-m2t: {message}", file=sys.stderr, flush=True)


def build(prefix: Path) -> None:
    """Build the vendored RTT and OCL into prefix (a fresh folder); raises with the log's tail."""
    work = prefix.with_name(prefix.name + ".work")
    shutil.rmtree(prefix, ignore_errors=True)
    shutil.rmtree(work, ignore_errors=True)
    jobs = str(os.cpu_count() or 2)
    log(f"building Orocos RTT 2.9 and OCL's deployer from {VENDOR.name}/ into {prefix} "
        f"({toolchain_versions()}, -j{jobs}; about 6 minutes on 2 cores, once per source/toolchain change)")
    started = time.monotonic()
    output = prefix.with_name(prefix.name + ".log")
    with output.open("w") as sink:
        result = subprocess.run(["bash", str(VENDOR / "build.sh"), str(prefix), str(VENDOR), str(work), jobs],
                                stdout=sink, stderr=subprocess.STDOUT, env={**os.environ, "OPT_FLAGS": OPTIMISATION})
    minutes = (time.monotonic() - started) / 60
    if result.returncode != 0 or not is_usable(prefix):
        lines = output.read_text(errors="replace").splitlines()
        detail = "\n".join(step_logs_tail(work) or lines[-LOG_TAIL_LINES:])
        raise OrocosBuildFailed(f"building Orocos RTT/OCL failed after {minutes:.1f} min (log {output}):\n{detail}")
    for line in output.read_text().splitlines():
        if line.startswith("== ") or "Elapsed" in line:
            log("  " + line.strip())
    shutil.rmtree(work, ignore_errors=True)
    complete_stamp(prefix).write_text(f"{toolchain_versions()}\n")
    log(f"built Orocos RTT and OCL in {minutes:.1f} min")


def step_logs_tail(work: Path) -> list[str]:
    """The tail of the newest step log of build.sh, which is where a failing compiler speaks."""
    logs = sorted((work / "logs").glob("*.log"), key=lambda p: p.stat().st_mtime)
    if not logs:
        return []
    return [f"== {logs[-1].name}", *logs[-1].read_text(errors="replace").splitlines()[-LOG_TAIL_LINES:]]


def ensure() -> Installation:
    """The installation to test against, building it into the cache when there is none."""
    started = time.monotonic()
    found = find()
    if found is not None:
        log(f"Orocos RTT and OCL: {found.prefix} ({found.origin})")
        return found
    if not VENDOR.is_dir():
        raise OrocosUnavailable("no Orocos RTT installation and no ../shared/vendor/orocos to build one from")
    prefix = cached_prefix()
    prefix.parent.mkdir(parents=True, exist_ok=True)
    with open(prefix.with_name(prefix.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # a second run waits for the first one's build
        if complete_stamp(prefix).is_file() and is_usable(prefix):
            log(f"Orocos RTT and OCL: {prefix} (built by a concurrent run, waited "
                f"{time.monotonic() - started:.0f} s)")
            return Installation(prefix, "cache")
        marker = failure_marker(prefix)
        marker.unlink(missing_ok=True)
        try:
            build(prefix)
        except OrocosBuildFailed as failure:
            marker.write_text(str(failure))
            raise
    return Installation(prefix, "cache")


def main(argv: list[str]) -> int:
    if argv[1:] not in (["ensure"], ["find"]):
        print("usage: orocos.py ensure|find", file=sys.stderr)
        return 2
    try:
        found = ensure() if argv[1] == "ensure" else installation()
    except OrocosUnavailable as reason:
        log(f"Orocos: {reason}")
        return 1
    except OrocosBuildFailed as failure:
        log(str(failure))
        return 1
    print(found.prefix)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""A PEP 517 build backend in the standard library alone, for this one package:
it writes the wheel (plinko_verify/*.py, its metadata and the plinko-verify
script) with zipfile, so installing needs nothing from a package index."""

import base64
import hashlib
import os
import tarfile
import zipfile

NAME = 'plinko_verify'
DIST = 'plinko_verify'
HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _project():
    """name, version, summary and scripts from pyproject.toml (the few lines this backend needs)."""
    values = {}
    scripts = {}
    section = None
    with open(os.path.join(HERE, 'pyproject.toml'), encoding='utf-8') as file:
        for line in file:
            line = line.strip()
            if line.startswith('['):
                section = line.strip('[]')
            elif '=' in line and not line.startswith('#'):
                key, _, value = (part.strip() for part in line.partition('='))
                if value.startswith('"') and value.endswith('"'):
                    value = value[1:-1]
                if section == 'project':
                    values[key] = value
                elif section == 'project.scripts':
                    scripts[key] = value
    return values, scripts


def _metadata():
    values, _ = _project()
    with open(os.path.join(HERE, 'README.md'), encoding='utf-8') as file:
        readme = file.read()
    return ('Metadata-Version: 2.1\nName: %s\nVersion: %s\nSummary: %s\nRequires-Python: %s\nLicense: MIT\n'
            'Description-Content-Type: text/markdown\n\n%s' % (
                values['name'], values['version'], values['description'], values['requires-python'], readme))


def _entry_points():
    _, scripts = _project()
    return '[console_scripts]\n' + ''.join('%s = %s\n' % item for item in scripts.items())


def _version():
    return _project()[0]['version']


def _sources():
    folder = os.path.join(HERE, NAME)
    return sorted(name for name in os.listdir(folder) if name.endswith('.py'))


def _dist_info():
    return '%s-%s.dist-info' % (DIST, _version())


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    info = os.path.join(metadata_directory, _dist_info())
    os.makedirs(info, exist_ok=True)
    for name, text in (('METADATA', _metadata()), ('entry_points.txt', _entry_points())):
        with open(os.path.join(info, name), 'w', encoding='utf-8') as file:
            file.write(text)
    return _dist_info()


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    filename = '%s-%s-py3-none-any.whl' % (DIST, _version())
    info = _dist_info()
    files = []
    for name in _sources():
        with open(os.path.join(HERE, NAME, name), 'rb') as file:
            files.append(('%s/%s' % (NAME, name), file.read()))
    files.append((info + '/METADATA', _metadata().encode('utf-8')))
    files.append((info + '/WHEEL', b'Wheel-Version: 1.0\nGenerator: plinko_build\nRoot-Is-Purelib: true\nTag: py3-none-any\n'))
    files.append((info + '/entry_points.txt', _entry_points().encode('utf-8')))
    record = ''.join('%s,sha256=%s,%d\n' % (path, _digest(data), len(data)) for path, data in files)
    record += info + '/RECORD,,\n'
    files.append((info + '/RECORD', record.encode('utf-8')))
    with zipfile.ZipFile(os.path.join(wheel_directory, filename), 'w', zipfile.ZIP_DEFLATED) as wheel:
        for path, data in files:
            wheel.writestr(zipfile.ZipInfo(path, date_time=(2026, 1, 1, 0, 0, 0)), data)
    return filename


def build_sdist(sdist_directory, config_settings=None):
    base = '%s-%s' % (DIST, _version())
    filename = base + '.tar.gz'
    with tarfile.open(os.path.join(sdist_directory, filename), 'w:gz') as sdist:
        for path in ['pyproject.toml', 'README.md', 'build_backend/plinko_build.py'] + ['%s/%s' % (NAME, n) for n in _sources()]:
            sdist.add(os.path.join(HERE, path), arcname='%s/%s' % (base, path))
    return filename


def _digest(data):
    return base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b'=').decode('ascii')

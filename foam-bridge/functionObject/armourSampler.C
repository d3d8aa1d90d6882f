// SPDX-License-Identifier: GPL-3.0-or-later
// armourSampler: the OpenFOAM function object of foam-bridge (see armourSampler.H).

#include "armourSampler.H"

#include "addToRunTimeSelectionTable.H"
#include "foamVersion.H"
#include "fvCFD.H"
#include "mapPolyMesh.H"
#include "OFstream.H"
#include "uniformDimensionedFields.H"
#include "wordRes.H"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>

// armour's version (solver/core/BuildInfo.hpp, which is C++17: declared here in C++11 form).
namespace armour { namespace core { std::string version(); } }

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(armourSampler, 0);
    addToRunTimeSelectionTable(functionObject, armourSampler, dictionary);
}
}

namespace
{

// Reductions of std::vector<double> over the ranks (sum, max): through a Foam::List.
void sumAll(std::vector<double>& v)
{
    if (!Foam::Pstream::parRun()) return;
    Foam::List<Foam::scalar> l(Foam::label(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i) l[Foam::label(i)] = v[i];
    Foam::Pstream::listCombineGather(l, Foam::plusEqOp<Foam::scalar>());
    Foam::Pstream::listCombineScatter(l);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = l[Foam::label(i)];
}

void maxAll(std::vector<double>& v)
{
    if (!Foam::Pstream::parRun()) return;
    Foam::List<Foam::scalar> l(Foam::label(v.size()));
    // "Nothing" is -inf in the core; it travels as -GREAT (finite: safe in any stream format) and
    // comes back as -inf.
    for (std::size_t i = 0; i < v.size(); ++i) l[Foam::label(i)] = std::max(v[i], -Foam::GREAT);
    Foam::Pstream::listCombineGather(l, Foam::maxEqOp<Foam::scalar>());
    Foam::Pstream::listCombineScatter(l);
    for (std::size_t i = 0; i < v.size(); ++i)
    {
        v[i] = l[Foam::label(i)] <= -Foam::GREAT ? -std::numeric_limits<double>::infinity() : l[Foam::label(i)];
    }
}

// The solver's command line (e.g. "interFoam -parallel"), for the storm file's history: the
// function object has no argList. Linux: /proc/self/cmdline, arguments separated by NULs.
std::string solverCommandLine()
{
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!s.empty() && s.back() == '\0') s.pop_back();
    for (char& c : s) if (c == '\0') c = ' ';
    return s;
}

} // namespace


Foam::functionObjects::armourSampler::armourSampler
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    twoD_(false),
    finished_(false),
    records_(0),
    seconds_(0.0),
    created_(std::chrono::steady_clock::now()),
    nCells_(0)
{
    read(dict);
}


Foam::functionObjects::armourSampler::~armourSampler()
{
    // The timeControl wrapper calls end() only if the last time step is also an execution time
    // that has not run yet, which is rarely the case: finish here otherwise. Every rank destroys
    // its function objects in the same order before MPI is finalised (argList outlives Time), so
    // the reductions in finish() are safe.
    finish();
}


bool Foam::functionObjects::armourSampler::read(const dictionary& dict)
{
    fvMeshFunctionObject::read(dict);

    armour::bridge::SamplerSettings s;
    const dictionary& grid = dict.subDict("grid");
    s.grid.xMin = grid.get<scalar>("xMin");
    s.grid.zMin = grid.get<scalar>("zMin");
    s.grid.dx = grid.get<scalar>("dx");
    s.grid.dz = grid.get<scalar>("dz");
    s.grid.nx = grid.get<label>("nx");
    s.grid.nz = grid.get<label>("nz");
    s.grid.trunkOrigin = dict.get<scalar>("trunkOrigin");
    s.grid.trunkLength = dict.get<scalar>("trunkLength");
    // A 2D tank holds at every y: the storm file then says uniform_along_y = 1.
    s.uniformAlongY = dict.lookupOrDefault<bool>("uniformAlongY", false);
    s.stillWaterLevel = dict.get<scalar>("stillWaterLevel");
    s.waterDensity = dict.get<scalar>("rho");
    scalar magG = 9.81;
    if (mesh_.time().foundObject<uniformDimensionedVectorField>("g"))
    {
        const vector g = mesh_.time().lookupObject<uniformDimensionedVectorField>("g").value();
        magG = mag(g);
        // The storm file's axes are fixed: z up (eta, the still water level, hydrostatics), x along
        // the waves, y along the trunk. Only |g| is used, so a case with y up would be sampled into
        // the wrong axes without a word. 1e-6 |g| of sideways gravity is round-off, not a tilt.
        if (!(g.z() < 0 && mag(g.x()) <= 1e-6*magG && mag(g.y()) <= 1e-6*magG))
        {
            FatalIOErrorInFunction(dict)
                << "armourSampler " << name() << ": constant/g: value = " << g
                << ": gravity must point along -z (the storm file has z up, x along the waves and y "
                << "along the trunk). Rotate the case so that z is up and the waves travel along x: "
                << "transformPoints -rotate '(<up axis> (0 0 1))' -rotateFields (e.g. '((0 1 0) (0 0 1))' "
                << "for a case with y up), then set g to (0 0 " << -magG << ") in constant/g"
                << exit(FatalIOError);
        }
    }
    s.gravity = dict.lookupOrDefault<scalar>("gravity", magG);
    s.wetAlpha = dict.lookupOrDefault<scalar>("wetAlpha", 0.5);
    if (dict.found("etaPlaneY")) s.etaPlaneY = dict.get<scalar>("etaPlaneY");
    if (dict.found("etaHalfWidth")) s.etaHalfWidth = dict.get<scalar>("etaHalfWidth");
    if (dict.found("etaColumnHalfWidth")) s.etaColumnHalfWidth = dict.get<scalar>("etaColumnHalfWidth");
    s.normalisationAmplitude = dict.lookupOrDefault<scalar>("normalisationAmplitude", 0.0);
    s.pressureReference = dict.lookupOrDefault<scalar>("pRef", 0.0);
    s.minimumSamples = dict.lookupOrDefault<label>("minimumSamples", 2);

    twoD_ = dict.lookupOrDefault<bool>("twoD", false);
    pName_ = dict.lookupOrDefault<word>("p", "p");
    UName_ = dict.lookupOrDefault<word>("U", "U");
    alphaName_ = dict.lookupOrDefault<word>("alpha", "alpha.water");
    file_ = dict.lookupOrDefault<fileName>("file", fileName("postProcessing")/name()/"storm.nc");
    file_.expand();
    if (!file_.isAbsolute()) file_ = mesh_.time().globalPath()/file_;
    debugFaceFile_ = dict.lookupOrDefault<fileName>("debugFaceFile", fileName());
    debugFaceFile_.expand();
    if (!debugFaceFile_.empty() && !debugFaceFile_.isAbsolute())
    {
        debugFaceFile_ = mesh_.time().globalPath()/debugFaceFile_;
    }
    writeOptions_.doublePrecision = dict.lookupOrDefault<bool>("doublePrecision", false);
    writeOptions_.deflateLevel = dict.lookupOrDefault<label>("deflate", 1);
    provenance_.title = dict.lookupOrDefault<string>("title", "");
    provenance_.comment = dict.lookupOrDefault<string>("comment", "");
    // The same provenance as foam-proxy's (docs/storm-file.md): the case, the OpenFOAM version
    // of the running solver, armour's version and the command (the solver's command line).
    fileName caseDir(mesh_.time().globalPath());
    caseDir.clean();
    provenance_.sourceCase = caseDir;
    // The running library's api (Debian's build leaves foamVersion::version empty): "v1912", as
    // foam-proxy writes it.
    provenance_.openfoamVersion =
        foamVersion::version.empty() ? "v" + std::to_string(foamVersion::api) : foamVersion::version;
    provenance_.software = "armour foam-bridge armourSampler " + armour::core::version();
    std::string solver = solverCommandLine();
    if (solver.empty())
    {
        solver = mesh_.time().controlDict().lookupOrDefault<word>("application", "OpenFOAM solver");
    }
    provenance_.command = solver + " (function object " + name() + ", type armourSampler)";
    writeOptions_.syncEachRecord = true;  // a killed run keeps every record in storm.nc.partial

    if (mesh_.dynamic())
    {
        // The faces, their voxels and the samples per voxel m are found once and m is written in
        // the storm file's header: a mesh that changes its topology (dynamicRefineFvMesh) or moves
        // (dynamicMotionSolverFvMesh) would invalidate all three. Refused before the first sample.
        FatalIOErrorInFunction(dict)
            << "armourSampler " << name() << ": the mesh is a " << meshType()
            << " (constant/dynamicMeshDict: dynamicFvMesh " << meshType() << "), a mesh that "
            << "changes during the run; armourSampler samples static meshes only (the unit faces, "
            << "their voxels and the samples per voxel of the storm file are fixed). Set "
            << "`dynamicFvMesh staticFvMesh;` in constant/dynamicMeshDict and refine the free-surface "
            << "band and the units beforehand (refineMesh, snappyHexMesh refinement regions)"
            << exit(FatalIOError);
    }

    if (!twoD_)
    {
        const wordRes names(dict.get<wordRes>("patches"));
        patchIDs_ = mesh_.boundaryMesh().patchSet(names).sortedToc();
        if (patchIDs_.empty())
        {
            FatalIOErrorInFunction(dict)
                << "armourSampler " << name() << ": no patch matches patches " << names
                << "; name the armour-unit wall patches (" << mesh_.boundaryMesh().names() << ")"
                << exit(FatalIOError);
        }
    }

    try
    {
        stats_.reset(new armour::bridge::VoxelStatistics(s));
    }
    catch (const std::invalid_argument& e)
    {
        FatalIOErrorInFunction(dict)
            << "armourSampler " << name() << ": " << e.what() << exit(FatalIOError);
    }
    setGeometry();
    return true;
}


void Foam::functionObjects::armourSampler::setGeometry()
{
    const armour::bridge::VoxelGrid& grid = stats_->grid();
    nCells_ = mesh_.nCells();
    std::vector<double> x, y, z;
    if (twoD_)
    {
        // The cell holding each voxel centre (in the plane y = etaPlaneY, the middle of a 2D mesh).
        DynamicList<label> cells;
        for (int iz = 0; iz < grid.nz(); ++iz)
        {
            for (int ix = 0; ix < grid.nx(); ++ix)
            {
                const point pt(grid.xCentre(ix), stats_->etaPlaneY(), grid.zCentre(iz));
                const label celli = mesh_.findCell(pt);
                if (celli < 0) continue;
                x.push_back(pt.x());
                y.push_back(grid.trunkMiddle());
                z.push_back(pt.z());
                cells.append(celli);
            }
        }
        sampleCells_.transfer(cells);
    }
    else
    {
        forAll(patchIDs_, i)
        {
            const vectorField& Cf = mesh_.boundary()[patchIDs_[i]].Cf();
            forAll(Cf, facei)
            {
                x.push_back(Cf[facei].x());
                y.push_back(Cf[facei].y());
                z.push_back(Cf[facei].z());
            }
        }
    }
    stats_->setSamplePoints(x, y, z);
    px_ = x;
    py_ = y;
    pz_ = z;
    std::vector<double> counts = stats_->localCounts();
    sumAll(counts);
    stats_->setCounts(counts);

    // The cells of the eta band (centre y within etaHalfWidth of etaPlaneY, centre x within
    // etaColumnHalfWidth of a column centre), as foam-proxy gets
    // them from the `sets` function object (type cellCentre, bounds of the band).
    const volVectorField& C = mesh_.C();
    DynamicList<label> etaCells;
    etaCellX_.clear();
    etaCellZ_.clear();
    forAll(C, celli)
    {
        const point& c = C[celli];
        const scalar hx = stats_->etaColumnHalfWidth();
        const scalar xLo = grid.xCentre(0) - hx, xHi = grid.xCentre(grid.nx() - 1) + hx;
        if (!stats_->inEtaBand(c.y()) || c.x() < xLo || c.x() > xHi) continue;
        etaCells.append(celli);
        etaCellX_.push_back(c.x());
        etaCellZ_.push_back(c.z());
    }
    etaCells_.transfer(etaCells);

    label points = label(stats_->samplePoints());
    label inGrid = 0;
    for (std::size_t i = 0; i < stats_->pointVoxel().size(); ++i) inGrid += stats_->pointVoxel()[i] >= 0;
    label etaCellCount = etaCells_.size();
    reduce(points, sumOp<label>());
    reduce(inGrid, sumOp<label>());
    reduce(etaCellCount, sumOp<label>());
    label voxels = 0;
    for (std::size_t i = 0; i < stats_->counts().size(); ++i) voxels += stats_->counts()[i] > 0;
    Info<< "armourSampler " << name() << ": " << points << (twoD_ ? " voxel centres in cells" : " unit faces")
        << ", " << inGrid << " in the " << grid.nx() << " x " << grid.nz() << " voxel grid, "
        << voxels << " voxels with data; eta from " << etaCellCount << " cells with centres within "
        << stats_->etaHalfWidth() << " m of y = " << stats_->etaPlaneY() << " m; writing " << file_
        << endl;
    if (!twoD_)
    {
        // Where the voxels sit: the solver's interpolation weight on voxels without data at the
        // unit faces (docs/foam-bridge.md).
        double weight = 0.0, faces = 0.0;
        stats_->addGapWeight(weight, faces);
        reduce(weight, sumOp<scalar>());
        reduce(faces, sumOp<scalar>());
        const double share = faces > 0 ? weight/faces : 0.0;
        Info<< "armourSampler " << name() << ": at the unit faces, " << 100.0*share
            << " % of the interpolation weight falls on voxels without data" << endl;
        if (share > armour::bridge::VoxelStatistics::kGapWeightWarning)
        {
            WarningInFunction
                << "armourSampler " << name() << ": "
                << armour::bridge::VoxelStatistics::gapWeightWarning(share).c_str() << endl;
        }
    }
    if (voxels == 0)
    {
        WarningInFunction
            << "armourSampler " << name() << ": no sample point falls in the voxel grid; check grid, "
            << "trunkOrigin and trunkLength" << endl;
    }
}


void Foam::functionObjects::armourSampler::collect
(
    armour::bridge::SampleValues& values,
    vector& force
) const
{
    if (!mesh_.foundObject<volScalarField>(pName_))
    {
        FatalErrorInFunction
            << "armourSampler " << name() << ": no field " << pName_
            << "; set `p` to the total (gauge) pressure field" << exit(FatalError);
    }
    const volScalarField& p = mesh_.lookupObject<volScalarField>(pName_);
    const volVectorField& U = mesh_.lookupObject<volVectorField>(UName_);
    const volScalarField& alpha = mesh_.lookupObject<volScalarField>(alphaName_);
    checkMeshUnchanged();
    values.resize(stats_->samplePoints());
    force = Zero;
    std::size_t k = 0;
    if (twoD_)
    {
        forAll(sampleCells_, i)
        {
            const label c = sampleCells_[i];
            values.p[k] = p[c];
            values.u[k] = U[c].x();
            values.v[k] = U[c].y();
            values.w[k] = U[c].z();
            values.alpha[k] = alpha[c];
            ++k;
        }
        return;
    }
    const scalar pRef = stats_->settings().pressureReference;
    forAll(patchIDs_, i)
    {
        const label patchi = patchIDs_[i];
        const scalarField& pp = p.boundaryField()[patchi];
        const scalarField& ap = alpha.boundaryField()[patchi];
        // U of the wall-adjacent cells: U on a no-slip wall is zero.
        const vectorField Ui(U.boundaryField()[patchi].patchInternalField());
        const vectorField& Sf = mesh_.boundary()[patchi].Sf();
        forAll(pp, facei)
        {
            values.p[k] = pp[facei];
            values.u[k] = Ui[facei].x();
            values.v[k] = Ui[facei].y();
            values.w[k] = Ui[facei].z();
            values.alpha[k] = ap[facei];
            force += (pp[facei] - pRef)*Sf[facei];
            ++k;
        }
    }
}


const Foam::word& Foam::functionObjects::armourSampler::meshType() const
{
    // fvMesh is a polyMesh and an lduMesh, both with a type(): the polyMesh's is the run-time
    // selected mesh class (staticFvMesh, dynamicRefineFvMesh, ...).
    return static_cast<const polyMesh&>(mesh_).type();
}


void Foam::functionObjects::armourSampler::checkMeshUnchanged() const
{
    // Never index past the arrays sized by setGeometry(): a mesh whose cells or unit faces changed
    // since (a mesh type that does not say it is dynamic, a topology change we were not told of)
    // stops the run here, naming what changed.
    label faces = 0;
    forAll(patchIDs_, i) faces += mesh_.boundary()[patchIDs_[i]].size();
    const label expected = twoD_ ? label(0) : label(stats_->samplePoints());
    if (mesh_.nCells() != nCells_ || faces != expected)
    {
        FatalErrorInFunction
            << "armourSampler " << name() << ": the " << meshType() << " mesh changed since the "
            << "sampler was set up (" << nCells_ << " -> " << mesh_.nCells() << " cells, " << expected
            << " -> " << faces << " unit faces on this rank); armourSampler samples static meshes only: "
            << "set `dynamicFvMesh staticFvMesh;` in constant/dynamicMeshDict" << exit(FatalError);
    }
}


void Foam::functionObjects::armourSampler::updateMesh(const mapPolyMesh&)
{
    checkMeshUnchanged();
    FatalErrorInFunction
        << "armourSampler " << name() << ": the " << meshType() << " mesh changed its topology; "
        << "armourSampler samples static meshes only: set `dynamicFvMesh staticFvMesh;` in "
        << "constant/dynamicMeshDict" << exit(FatalError);
}


void Foam::functionObjects::armourSampler::movePoints(const polyMesh&)
{
    FatalErrorInFunction
        << "armourSampler " << name() << ": the " << meshType() << " mesh moved; armourSampler "
        << "samples static meshes only (the unit faces are binned into voxels once): set "
        << "`dynamicFvMesh staticFvMesh;` in constant/dynamicMeshDict" << exit(FatalError);
}


bool Foam::functionObjects::armourSampler::execute()
{
    if (finished_) return true;
    const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    const double t = mesh_.time().value();

    armour::bridge::SampleValues values;
    vector force(Zero);
    collect(values, force);
    std::vector<double> sums;
    stats_->sums(values, sums);
    sumAll(sums);

    const volScalarField& alpha = mesh_.lookupObject<volScalarField>(alphaName_);
    std::vector<double> levels;
    stats_->initColumnLevels(levels);
    for (int pass = 0; pass < armour::bridge::VoxelStatistics::kEtaPasses; ++pass)
    {
        forAll(etaCells_, i)
        {
            stats_->addEtaCell(pass, levels, etaCellX_[i], etaCellZ_[i], alpha[etaCells_[i]]);
        }
        maxAll(levels);
    }

    armour::storm::StormRecord record;
    stats_->finishRecord(t, sums, levels, !twoD_, record);
    if (!twoD_) stats_->addDeviations(values, record, histogram_);
    reduce(force, sumOp<vector>());

    if (!debugFaceFile_.empty())
    {
        // Per-face samples for verification (small cases only), one file per rank:
        // time x y z p alpha.
        fileName f = debugFaceFile_;
        if (Pstream::parRun()) f = f + ".proc" + Foam::name(Pstream::myProcNo());
        if (records_ == 0) mkDir(f.path());
        FILE* out = std::fopen(f.c_str(), records_ == 0 ? "w" : "a");
        if (out)
        {
            for (std::size_t i = 0; i < values.size(); ++i)
            {
                std::fprintf
                (
                    out, "%.10g %.12g %.12g %.12g %.12g %.12g\n",
                    t, px_[i], py_[i], pz_[i], values.p[i], values.alpha[i]
                );
            }
            std::fclose(out);
        }
    }

    if (Pstream::master())
    {
        try
        {
            if (!writer_)
            {
                mkDir(file_.path());
                armour::storm::StormHeader header = stats_->header(!twoD_);
                header.provenance = provenance_;
                writer_.reset(new armour::storm::StormWriter(file_, header, writeOptions_));
            }
            stats_->observeEta(record.eta);
            writer_->append(record);
        }
        catch (const std::exception& e)
        {
            FatalErrorInFunction
                << "armourSampler " << name() << ": " << e.what() << exit(FatalError);
        }
        times_.push_back(t);
        forces_.push_back(force.x());
        forces_.push_back(force.y());
        forces_.push_back(force.z());
    }
    ++records_;
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return true;
}


bool Foam::functionObjects::armourSampler::write()
{
    // Everything is written in execute(): one storm record per execution.
    return true;
}


void Foam::functionObjects::armourSampler::finish()
{
    if (finished_) return;
    finished_ = true;
    std::vector<double>& h = histogram_.data();
    sumAll(h);
    double seconds = seconds_;
    reduce(seconds, maxOp<scalar>());
    if (!Pstream::master()) return;

    // No mesh_ or Time here: finish() may run from the destructor, after the solver has destroyed
    // the mesh and while Time is being destroyed.
    const std::string source =
        "armourSampler function object " + name() + " in " + provenance_.sourceCase;
    try
    {
        if (!writer_ || records_ < 2)
        {
            WarningInFunction
                << "armourSampler " << name() << ": " << records_
                << " record(s): a storm file needs at least 2; nothing finished (check executeInterval)"
                << endl;
            return;
        }
        const armour::storm::Variability v = stats_->variability(histogram_, source);
        writer_->setVariability(v);
        writer_->finish();
        Info<< "armourSampler " << name() << ": wrote " << file_ << " (" << records_ << " records)" << nl;
        if (v.present)
        {
            for (int c = 0; c < armour::storm::kVariabilityClasses; ++c)
            {
                const armour::storm::WeibullFit& f = v.classes[c];
                Info<< "    " << armour::storm::kVariabilityClassNames[c] << ": shape " << f.shape
                    << " scale " << f.scale << " KS " << f.ksStatistic << " from " << label(f.samples)
                    << " deviations" << nl;
            }
        }
    }
    catch (const std::exception& e)
    {
        FatalErrorInFunction
            << "armourSampler " << name() << ": " << e.what() << exit(FatalError);
    }
    if (!twoD_)
    {
        // The force of the sampled face pressures (sum (p - pRef) S_f), to check against `forces`.
        OFstream out(file_.lessExt() + "-pressure-force.csv");
        out.precision(12);
        out << "time_s,Fx_N,Fy_N,Fz_N" << nl;
        for (std::size_t k = 0; k < times_.size(); ++k)
        {
            out << times_[k] << ',' << forces_[3*k] << ',' << forces_[3*k + 1] << ','
                << forces_[3*k + 2] << nl;
        }
    }
    Info<< "armourSampler " << name() << ": " << seconds << " s in the sampler over " << records_
        << " records (" << 1e3*seconds/max(records_, label(1)) << " ms per record); "
        << std::chrono::duration<double>(std::chrono::steady_clock::now() - created_).count()
        << " s since the function object was created" << endl;
}


bool Foam::functionObjects::armourSampler::end()
{
    finish();
    return true;
}

// distrib/study.h — one study shared by the ranks of an MPI job. Every rank runs the same study in step;
// each of its renders (the reference and every row) is a renderDistributed, so its pixels are those of
// the single-process study and so are the rows; rank 0 alone measures, writes the files and reports.
// Rank 0's decisions from its files (a cached reference) are broadcast; bad input met while preparing, on
// any rank, stops every rank with one message.
#pragma once

#include "distrib/mpi_job.h"
#include "study/study.h"

namespace symphong {

/// runStudy across the job (a plain runStudy in a job of one rank). Collective. `cancel` matters on rank 0
/// only: it stops handing out tiles, and every rank then ends the study as cancelled. Bad input agreed by
/// all ranks throws InputError on every rank; an error that only rank 0 meets later (its disk filling
/// up) is printed from rank 0 and ends the whole job (MPI_Abort), since the others would wait for it.
StudyOutcome runStudyDistributed(const MpiJob& job, const StudyConfig& config, const std::atomic<bool>* cancel, bool showProgress);

}  // namespace symphong

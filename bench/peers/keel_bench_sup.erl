%% The Erlang/OTP peer of `keel bench recovery`: a one_for_one supervisor over one gen_server
%% (keel_bench_worker), and the driver that crashes the worker n times and times each restart.
%% Run by bench/harness/peers.cpp, after erlc into a temporary directory:
%%   erl -noshell -noinput -pa DIR -eval 'keel_bench_sup:main(N).'
%% Per fault: T0 = erlang:monotonic_time(nanosecond) in the worker just before its badarith;
%% T1 = the same clock at the end of the new worker's init, started by the supervisor.
%% Output, one item per line, after the last fault (nothing is printed while faults run):
%%   otp <release>
%%   latency <T1 - T0 in ns>      one per recovered fault
%%   failed <count>               faults whose crash or restart did not arrive within 2 s
%%   done
%% then halt(0). A setup error prints `error <reason>` and halts with 1.
%% One warm-up fault comes first, not counted: the first crash loads module `sys` (erl runs in
%% interactive mode, loading code on first use; an embedded release would have it loaded).
-module(keel_bench_sup).
-behaviour(supervisor).

-export([main/1, init/1]).

-define(BOUND_MS, 2000).  % per step of a fault: crash report, then restart
-define(SETTLE_MS, 10).   % before the first fault, as keel's own trials
-define(BETWEEN_MS, 3).   % between faults, as keel's own trials

%% Restart intensity so high the supervisor never gives up during a run (and the period of the
%% bookkeeping as short as OTP allows: one second).
init(Driver) ->
    Flags = #{strategy => one_for_one, intensity => 1000000000, period => 1},
    Worker = #{id => worker,
               start => {keel_bench_worker, start_link, [Driver]},
               restart => permanent,
               shutdown => brutal_kill,
               type => worker},
    {ok, {Flags, [Worker]}}.

main(N) when is_integer(N), N >= 0 ->
    %% No crash reports, supervisor reports or progress reports: each would format and write
    %% a report per fault. The peer is measured at its fastest, as keel is with its log async.
    ok = logger:set_primary_config(level, none),
    process_flag(trap_exit, true),
    {ok, _Sup} = supervisor:start_link({local, ?MODULE}, ?MODULE, self()),
    case warm_up() of
        {ok, Worker} ->
            timer:sleep(?SETTLE_MS),
            {Latencies, Failed} = faults(N, Worker, [], 0),
            report(lists:reverse(Latencies), Failed),
            halt(0);
        {error, Reason} ->
            io:format("error ~s~n", [Reason]),
            halt(1)
    end.

%% The first worker, crashed once (uncounted); returns its replacement.
warm_up() ->
    case await_ready() of
        {ok, First} ->
            gen_server:cast(First, crash),
            case one_fault(First) of
                {ok, _Latency, Worker} -> {ok, Worker};
                failed -> {error, "warm-up fault not recovered within 2 s"}
            end;
        timeout ->
            {error, "first worker not ready within 2 s"}
    end.

faults(0, _Worker, Latencies, Failed) ->
    {Latencies, Failed};
faults(K, Worker, Latencies, Failed) ->
    gen_server:cast(Worker, crash),
    case one_fault(Worker) of
        {ok, Latency, Next} ->
            timer:sleep(?BETWEEN_MS),
            faults(K - 1, Next, [Latency | Latencies], Failed);
        failed ->
            faults(K - 1, resync(), Latencies, Failed + 1)
    end.

%% The crash report of Worker, then the ready report of its replacement.
one_fault(Worker) ->
    receive
        {crash, Worker, T0} ->
            receive
                {ready, Next, T1} -> {ok, T1 - T0, Next}
            after ?BOUND_MS -> failed
            end
    after ?BOUND_MS -> failed
    end.

%% After a lost fault: drop stale reports and carry on with whichever worker now runs.
resync() ->
    flush(),
    [{worker, Pid, worker, _}] = supervisor:which_children(?MODULE),
    Pid.

flush() ->
    receive
        {crash, _, _} -> flush();
        {ready, _, _} -> flush()
    after 0 -> ok
    end.

await_ready() ->
    receive
        {ready, Worker, _T1} -> {ok, Worker}
    after ?BOUND_MS -> timeout
    end.

report(Latencies, Failed) ->
    io:format("otp ~s~n", [erlang:system_info(otp_release)]),
    [io:format("latency ~b~n", [L]) || L <- Latencies],
    io:format("failed ~b~ndone~n", [Failed]).

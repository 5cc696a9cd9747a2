%% The gen_server the Erlang peer's supervisor (keel_bench_sup) restarts. It reports to the
%% driver at the end of init ({ready, self(), T1}) and, on the cast `crash`, just before it dies
%% of a badarith ({crash, self(), T0}); both times from erlang:monotonic_time(nanosecond).
-module(keel_bench_worker).
-behaviour(gen_server).

-export([start_link/1, init/1, handle_call/3, handle_cast/2]).

-record(state, {driver :: pid(), zero = 0 :: integer()}).

start_link(Driver) ->
    gen_server:start_link(?MODULE, Driver, []).

init(Driver) ->
    T1 = erlang:monotonic_time(nanosecond),
    Driver ! {ready, self(), T1},
    {ok, #state{driver = Driver}}.

handle_call(_Request, _From, State) ->
    {reply, ok, State}.

%% A real arithmetic fault: the divisor comes from the state, so the compiler cannot see it.
handle_cast(crash, State = #state{driver = Driver, zero = Zero}) ->
    T0 = erlang:monotonic_time(nanosecond),
    Driver ! {crash, self(), T0},
    {noreply, State#state{zero = 1 div Zero}}.

-- | Why a value came out: the events an evaluator emits while it runs with
-- tracing on, and their two renderings (text for a reader, one JSON object
-- per line for tools). docs/trace.md describes both.
--
-- The evaluators emit the events from the meaning functions themselves (a
-- read where a variable is read, a rule where a policy or a rule decides an
-- outcome); tracing off, nothing is emitted and nothing is kept. A
-- 'Tracer' keeps the events of a run, and leaves out the iterations of a
-- loop after the first few unless told to keep everything.
module Stref.Trace
  ( -- * Events
    Event (..)
  , Decision (..)
  , decision
  , ruled
  , citedRules
    -- * Collecting
  , Tracer
  , newTracer
  , emit
  , tracerEvents
  , keptIterations
    -- * Reading
  , Item (..)
  , items
  , renderText
  , itemJson
  , renderJsonLines
  , watching
  , parting
  ) where

import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.ByteString.Lazy as BL
import Data.List (nubBy)
import Data.Maybe (fromMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import Stref.Policy (Policies (..), policyAssignments, citedIds)

-- | A point where a catalogue rule decided an outcome: its id, the policy
-- whose alternative was in force there (if a policy decided), and what it
-- did, in words.
data Decision = Decision
  { dRules :: [Text] -- ^ the rule's ids, in every catalogue that has it
  , dPolicy :: Maybe Text
  , dSays :: Text
  }
  deriving (Eq, Show)

-- | A rule that no policy parameterises.
decision :: [Text] -> Text -> Decision
decision rules = Decision rules Nothing

-- | A rule whose outcome the named policy chose.
ruled :: [Text] -> Text -> Text -> Decision
ruled rules policy = Decision rules (Just policy)

-- | The ids a trace under these policies cites: those of the dialect's
-- catalogue ('pCatalogue'), or all when it has none of them.
citedRules :: Policies -> Decision -> [Text]
citedRules pol d = citedIds pol (dRules d)

-- | What an evaluator emits, in the order it happens. Lines are source
-- lines; values are already rendered as the dialect writes them.
data Event
  = Cycle !Int -- ^ a scan cycle (a module call) begins, counted from 1
  | Read !Int Text Text -- ^ a variable read: line, name, value
  | Wrote !Int Text Text -- ^ a variable written: line, name, value
  | Rule !Int Decision -- ^ a rule decided something on this line
  | Statement !Int -- ^ the statement on this line completed
  | Branch !Int Text -- ^ IF or CASE chose: line, which part runs
  | LoopEnter !Int Text -- ^ a loop starts: line, its bounds in words
  | Iteration !Int !Int -- ^ the n-th iteration of the loop of this line begins
  | LoopExit !Int !Int -- ^ the loop of this line ended after n iterations
  | Call !Int Text [(Text, Text)] -- ^ a call: line, callee, arguments
  | Return !Int Text [(Text, Text)] -- ^ the callee returned: its results
  | Failure !Int (Maybe Text) Text -- ^ a runtime error: line, rule, message
  | Elided !Int !Int -- ^ the loop of this line ran n iterations not shown
  deriving (Eq, Show)

-- | The first iterations of each loop that a summarised trace shows.
keptIterations :: Int
keptIterations = 3

-- | A loop being run: how many of its iterations have begun.
newtype LoopState = LoopState {lsIteration :: Int}
  deriving (Eq, Show)

-- | The events of a run so far (newest first), and the loops being run.
data Tracer = Tracer
  { trAll :: !Bool
  , trEvents :: [Event]
  , trLoops :: [LoopState]
  }
  deriving (Eq, Show)

-- | A tracer; with @True@ it keeps every iteration of every loop.
newTracer :: Bool -> Tracer
newTracer every = Tracer every [] []

-- | The events, oldest first.
tracerEvents :: Tracer -> [Event]
tracerEvents = reverse . trEvents

-- | Keep an event, unless it happens in an iteration that is left out
-- (past 'keptIterations' of its loop or of a loop around it); a loop whose
-- iterations were left out gets an 'Elided' count when it ends. Runtime
-- errors are always kept, and end every loop being run (the call stops),
-- so that what is told after them is kept too; a cycle begins with no loop
-- running.
emit :: Event -> Tracer -> Tracer
emit ev t = case ev of
  LoopEnter {} -> keep (t {trLoops = LoopState 0 : trLoops t})
  Iteration _ n -> case trLoops t of
    _ : rest -> keep (t {trLoops = LoopState n : rest})
    [] -> keep t
  LoopExit l n -> case trLoops t of
    _ : rest ->
      let t' = t {trLoops = rest}
          skipped = n - keptIterations
       in if hidden t'
            then t'
            else
              if not (trAll t) && skipped > 0
                then push ev (push (Elided l skipped) t')
                else push ev t'
    [] -> keep t
  Failure {} -> push ev (t {trLoops = []})
  Cycle _ -> push ev (t {trLoops = []})
  _ -> keep t
  where
    keep t' = if hidden t' then t' else push ev t'
    push e t' = t' {trEvents = e : trEvents t'}
    hidden t' = not (trAll t') && any ((> keptIterations) . lsIteration) (trLoops t')

------------------------------------------------------------------------------
-- Reading

-- | An event with the reads, writes and rule decisions of its line that
-- happened while it ran: what one line of the text trace shows.
data Item = Item
  { itEvent :: Event
  , itReads :: [(Text, Text)]
  , itWrites :: [(Text, Text)]
  , itRules :: [Decision]
  }
  deriving (Eq, Show)

-- | Group the events: reads, writes and rules are attached to the next
-- event of the same line that completes something (a statement, a
-- branch, a loop's start, a call, an error); those left over (a line that
-- never completed) stand alone.
items :: [Event] -> [Item]
items = quiet . go []
  where
    -- a call statement adds nothing to its call's return
    quiet = \case
      a@(Item (Return l _ _) _ _ _) : Item (Statement l') [] [] [] : rest | l == l' -> quiet (a : rest)
      x : rest -> x : quiet rest
      [] -> []
    go pending [] = flush pending
    go pending (e : es) = case e of
      Read {} -> go (e : pending) es
      Wrote {} -> go (e : pending) es
      Rule {} -> go (e : pending) es
      _ ->
        let (mine, others) = span ((== lineOf e) . lineOf) pending
         in flush others ++ attach e (reverse mine) : go [] es
    flush pending = [Item p [] [] [] | p <- reverse pending, standalone p]
    standalone = \case
      Rule {} -> True
      Wrote {} -> True
      _ -> False
    attach e evs =
      Item
        e
        (nubBy (\a b -> fst a == fst b) [(n, v) | Read _ n v <- evs])
        [(n, v) | Wrote _ n v <- evs]
        [d | Rule _ d <- evs]

lineOf :: Event -> Int
lineOf = \case
  Cycle _ -> 0
  Read l _ _ -> l
  Wrote l _ _ -> l
  Rule l _ -> l
  Statement l -> l
  Branch l _ -> l
  LoopEnter l _ -> l
  Iteration l _ -> l
  LoopExit l _ -> l
  Call l _ _ -> l
  Return l _ _ -> l
  Failure l _ _ -> l
  Elided l _ -> l

-- | The text trace: one line per item, the source line it ran (from the
-- given lookup) and what happened, rules with their ids and the policy
-- alternative in force; calls and loop bodies indented.
renderText :: Policies -> (Int -> Text) -> [Item] -> [Text]
renderText pol source = go 0
  where
    go _ [] = []
    go depth (it : rest) = case itEvent it of
      Cycle n -> ("cycle " <> tshow n) : go 0 rest
      Call l f args -> here depth l ("call " <> f <> " " <> parens (assigns args)) : go (depth + 1) rest
      Return l f outs -> here (max 0 (depth - 1)) l (f <> " returns " <> commaList (assigns outs)) : go (max 0 (depth - 1)) rest
      LoopEnter {} -> render depth it ++ go (depth + 1) rest
      LoopExit {} -> render (max 0 (depth - 1)) it ++ go (max 0 (depth - 1)) rest
      Elided {} -> render (max 0 (depth - 1)) it ++ go depth rest
      _ -> render depth it ++ go depth rest
    render depth it =
      let l = lineOf (itEvent it)
          what = case itEvent it of
            Statement _ -> effects it
            Branch _ b -> joinParts [reads it, b, writes it]
            LoopEnter _ b -> joinParts [reads it, b, writes it]
            Iteration _ n -> joinParts ["iteration " <> tshow n, reads it, writes it]
            LoopExit _ n -> joinParts ["loop ends after " <> tshow n <> " iteration" <> (if n == 1 then "" else "s"), reads it, writes it]
            Elided _ n -> "... " <> tshow n <> " more iteration" <> (if n == 1 then "" else "s") <> " not shown (--trace-all shows every one)"
            Failure _ rule msg -> "runtime error: " <> msg <> maybe "" (\r -> " (" <> r <> ")") rule
            Wrote _ n v -> n <> " := " <> v
            Rule _ _ -> ""
            _ -> effects it
          plain = case itEvent it of
            Iteration {} -> True
            LoopExit {} -> True
            Elided {} -> True
            _ -> False
          first = if plain then blank depth <> what else here depth l what
       in first : [blank (depth + 1) <> ruleText d | d <- itRules it ++ [d | Rule _ d <- [itEvent it]]]
    here depth l what =
      let src = T.strip (source l)
          left = T.justifyRight 5 ' ' (tshow l) <> " | " <> T.replicate (2 * depth) " " <> src
       in if T.null what then left else T.justifyLeft 44 ' ' left <> "  " <> what
    blank depth = T.replicate 8 " " <> T.replicate (2 * depth) " "
    reads it = commaList [n <> " = " <> v | (n, v) <- itReads it]
    writes it = if null (itWrites it) then "" else "-> " <> commaList [n <> " := " <> v | (n, v) <- itWrites it]
    effects it = joinParts [reads it, writes it]
    ruleText d = "rule " <> T.intercalate ", " (citedRules pol d) <> ": " <> dSays d <> maybe "" (\p -> " (" <> p <> "=" <> alternative p <> ")") (dPolicy d)
    alternative p = fromMaybe "?" (lookup p (policyAssignments pol))
    joinParts = T.intercalate "; " . filter (not . T.null)
    assigns xs = [n <> " := " <> v | (n, v) <- xs]
    commaList = T.intercalate ", "
    parens xs = "(" <> commaList xs <> ")"

-- | One item as a JSON object (docs/trace.md lists the fields).
itemJson :: Policies -> Item -> A.Value
itemJson pol it = A.object (kind ++ attached)
  where
    field k v = K.fromText k A..= v
    pairs xs = A.object [K.fromText n A..= v | (n, v) <- xs]
    kind = case itEvent it of
      Cycle n -> [field "event" ("cycle" :: Text), field "cycle" n]
      Statement l -> [field "event" ("statement" :: Text), field "line" l]
      Branch l b -> [field "event" ("branch" :: Text), field "line" l, field "taken" b]
      LoopEnter l b -> [field "event" ("loop" :: Text), field "line" l, field "bounds" b]
      Iteration l n -> [field "event" ("iteration" :: Text), field "line" l, field "iteration" n]
      LoopExit l n -> [field "event" ("loop-end" :: Text), field "line" l, field "iterations" n]
      Elided l n -> [field "event" ("not-shown" :: Text), field "line" l, field "iterations" n]
      Call l f args -> [field "event" ("call" :: Text), field "line" l, field "callee" f, field "arguments" (pairs args)]
      Return l f outs -> [field "event" ("return" :: Text), field "line" l, field "callee" f, field "results" (pairs outs)]
      Failure l rule msg -> [field "event" ("error" :: Text), field "line" l, field "rule" rule, field "message" msg]
      Read l n v -> [field "event" ("read" :: Text), field "line" l, field "reads" (pairs [(n, v)])]
      Wrote l n v -> [field "event" ("write" :: Text), field "line" l, field "writes" (pairs [(n, v)])]
      Rule l d -> [field "event" ("rule" :: Text), field "line" l, field "rules" [ruleJson d]]
    attached =
      [field "reads" (pairs (itReads it)) | not (null (itReads it))]
        ++ [field "writes" (pairs (itWrites it)) | not (null (itWrites it))]
        ++ [field "rules" (map ruleJson (itRules it)) | not (null (itRules it))]
    ruleJson d =
      A.object $
        [field "rules" (citedRules pol d), field "says" (dSays d)]
          ++ concat [[field "policy" p, field "alternative" (fromMaybe "?" (lookup p (policyAssignments pol)))] | Just p <- [dPolicy d]]

-- | The JSON event stream: one object per line.
renderJsonLines :: Policies -> [Item] -> [Text]
renderJsonLines pol = map (TE.decodeUtf8 . BL.toStrict . A.encode . itemJson pol)

-- | Only the items that read or write one of the named variables (a name
-- also matches its elements and fields: @V@ matches @V[2]@ and @V.X@), the
-- cycles and the runtime errors; no names keeps everything.
watching :: [Text] -> [Item] -> [Item]
watching [] = id
watching names = filter keep
  where
    keep it = case itEvent it of
      Cycle _ -> True
      Failure {} -> True
      _ -> any mentions (map fst (itReads it ++ itWrites it) ++ [n | Wrote _ n _ <- [itEvent it]])
    mentions n = any (\w -> let n' = T.toUpper n in n' == w || any (\c -> (w <> c) `T.isPrefixOf` n') ["[", "."]) (map T.toUpper names)

tshow :: Show a => a -> Text
tshow = T.pack . show

-- | The number of items several traces share from their start, when they
-- part (a value, a branch or a rule's outcome differs); Nothing when they
-- are the same throughout.
parting :: [[Item]] -> Maybe Int
parting traces = go 0 traces
  where
    go k ts = case mapM uncons' ts of
      Nothing
        | all null ts -> Nothing
        | otherwise -> Just k -- one ended before the others
      Just heads
        | all (== head firsts) firsts -> go (k + 1) (map snd heads)
        | otherwise -> Just k
        where
          firsts = map fst heads
    uncons' = \case
      x : xs -> Just (x, xs)
      [] -> Nothing

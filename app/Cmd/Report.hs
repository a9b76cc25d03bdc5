-- | @stref report merge FILE...@: merge the reports of a corpus run split
-- into shards (@stref conformance --shard I/N --format json|junit --output
-- F@, one machine or CI job per shard) into the report of the whole run, of
-- the same format (conformance/README.md, "Sharded runs"). Exit 1 when a
-- case of the merged run failed (as @stref conformance@ would have), 2 when
-- the files cannot be merged (unreadable, no report, reports of different
-- formats or runs, a case in two of them).
module Cmd.Report (Cmd.Report.command) where

import Control.Exception (IOException, try)
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.List (nub)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Merge
import Stref.Conformance.Report (Totals (..), summaryLine)
import System.Directory (doesDirectoryExist, doesFileExist)
import System.Exit
import System.IO (stderr)

data MergeOpts = MergeOpts
  { moFiles :: [FilePath]
  , moOutput :: Maybe FilePath
  }

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "report"
    ( info
        (hsubparser mergeCommand)
        (progDesc "Work with the reports of `stref conformance`")
    )
  where
    mergeCommand =
      Options.Applicative.command
        "merge"
        ( info
            (merge <$> mergeOpts)
            ( progDesc
                "Merge the JSON (or JUnit XML) reports of the shards of one run (stref conformance --shard I/N --format json --output F) into the report of the whole run, in the same format; exit 1 if a case failed"
            )
        )
    mergeOpts =
      MergeOpts
        <$> some (strArgument (metavar "FILE..." <> help "The shards' reports, all JSON or all JUnit XML"))
        <*> optional (strOption (long "output" <> metavar "FILE" <> help "Write the merged report to FILE and the summary line to stdout"))

usage :: Text -> IO ExitCode
usage msg = TIO.hPutStrLn stderr ("stref report merge: " <> msg) >> pure (ExitFailure 2)

merge :: MergeOpts -> IO ExitCode
merge o = do
  read' <- mapM readReport (moFiles o)
  case sequence read' of
    Left e -> usage e
    Right inputs -> case nub (map (detectFormat . snd) inputs) of
      [Just JsonReport] -> case mergeJson inputs of
        Left e -> usage e
        Right (report, t) -> finish report t
      [Just JunitReport] -> case mergeJunit [(f, TE.decodeUtf8With TE.lenientDecode (BL.toStrict b)) | (f, b) <- inputs] of
        Left e -> usage e
        Right (report, (tests, failures, errors, skipped)) ->
          -- JUnit counts a malformed case as an error; the line says so
          finishJunit (BL.fromStrict (TE.encodeUtf8 report)) tests failures errors skipped
      formats
        | Nothing `elem` formats ->
            usage ("not a report of stref conformance --format json or junit: " <> T.intercalate ", " [T.pack f | (f, b) <- inputs, detectFormat b == Nothing] <> " (a text report cannot be merged; write the shards' reports with --format json)")
        | otherwise -> usage "the reports are of different formats (JSON and JUnit XML); merge the reports of one format"
  where
    readReport f = do
      isDir <- doesDirectoryExist f
      isFile <- doesFileExist f
      if isDir
        then pure (Left (T.pack f <> " is a directory; give the report files"))
        else
          if not isFile
            then pure (Left ("no such file: " <> T.pack f))
            else either (\(e :: IOException) -> Left (T.pack f <> ": " <> T.pack (show e))) (Right . (f,)) <$> try (BL.readFile f)
    write report = case moOutput o of
      Just file -> BL.writeFile file report >> pure True
      Nothing -> BLC.putStr report >> pure False
    finish report t = do
      toFile <- write report
      if toFile then TIO.putStrLn (summaryLine t) else pure ()
      pure (if tFailed t + tEngineError t > 0 then ExitFailure 1 else ExitSuccess)
    finishJunit report tests failures errors skipped = do
      toFile <- write report
      if toFile
        then TIO.putStrLn (T.pack (show tests) <> " tests, " <> T.pack (show failures) <> " failures, " <> T.pack (show errors) <> " errors, " <> T.pack (show skipped) <> " skipped (unsupported included)")
        else pure ()
      pure (if failures + errors > 0 then ExitFailure 1 else ExitSuccess)
